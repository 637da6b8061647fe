// Atomic file output: write to a temporary file beside the target, rename over it on success.
// A failed or interrupted write never leaves a partial file at the target path.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace msh::io {

// Writes `bytes` to `path` atomically. Throws msh::InputError (naming the path) when the directory does not
// exist or is not writable, when the target exists and is not a regular file (a device, FIFO, socket or
// directory: never replaced), or when any write, flush or close fails; the target is then untouched.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::byte> bytes);
void write_file_atomic(const std::filesystem::path& path, std::string_view text);

// For writers that need a file name (e.g. OpenEXR, libpng): a temporary path in the target's directory that
// commit() renames to the target; the destructor removes it if commit() was not called.
class AtomicPath {
 public:
  explicit AtomicPath(std::filesystem::path target);
  ~AtomicPath();
  AtomicPath(const AtomicPath&) = delete;
  AtomicPath& operator=(const AtomicPath&) = delete;
  const std::filesystem::path& temp() const { return temp_; }
  void commit();

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
  int slot_ = -1;  // the signal handler's record of temp_
};

// Temporary files (".NAME.tmp-PID-N") are removed however the run ends:
//  - by the destructor on an error;
//  - on SIGINT, SIGTERM or SIGHUP once install_temporary_cleanup() has run (the CLI calls it first): the
//    handler unlinks every temporary in flight, then the signal takes its default action (the exit status
//    says the run was killed);
//  - at the next run: the first write into a directory removes the temporaries there whose process is gone
//    (a SIGKILL, a power cut).
void install_temporary_cleanup();

// Renames the directory `from` (a folder written whole under a temporary name) to `to`, and the files an
// OutputFolder recorded under `from` are recorded under `to` instead: its list names the files where they
// end up, not the temporary's (whose name holds the process id). Throws std::filesystem::filesystem_error.
void rename_recorded_directory(const std::filesystem::path& from, const std::filesystem::path& to);

// A run's output folder, replaced or completed as a whole. Every file committed under `dir` while the object
// lives is recorded (every writer of the library goes through AtomicPath); finish() writes their list to
// DIR/.microshadow-files (written last: a folder without it, or with an older one, is an incomplete run) and
// removes the files the previous run's list named that this run did not write (never a file the tool did
// not write), with the directories they leave empty. Without finish() (an error, a signal) nothing is
// removed: the previous list stays, and the next run completes the folder. The run's writers create `dir`
// (the constructor only refuses a path that exists and is not a directory).
class OutputFolder {
 public:
  explicit OutputFolder(std::filesystem::path dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  // The files removed as stale, relative to dir, sorted.
  std::vector<std::string> finish();
  static constexpr const char* kManifest = ".microshadow-files";

 private:
  std::filesystem::path dir_;
  std::size_t id_;
};

}  // namespace msh::io

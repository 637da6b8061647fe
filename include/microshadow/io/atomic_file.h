// Atomic file output: write to a temporary file beside the target, rename over it on success.
// A failed or interrupted write never leaves a partial file at the target path.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string_view>

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
};

}  // namespace msh::io

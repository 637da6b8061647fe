#include <fmt/format.h>
#include <fmt/std.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace msh::io {
namespace fs = std::filesystem;

namespace {
fs::path temp_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() /
         fmt::format(".{}.tmp-{}-{}", target.filename().string(), ::getpid(), counter++);
}
void check_directory(const fs::path& target) {
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(fmt::format("cannot write '{}': no such directory", target.string()));
}
}  // namespace

AtomicPath::AtomicPath(fs::path target) : target_(std::move(target)) {
  if (target_.filename().empty())
    throw InputError(fmt::format("cannot write '{}': not a file name", target_.string()));
  check_directory(target_);
  // Replacing a device, FIFO or socket by a regular file would be a surprise (`convert x.npy /dev/null`);
  // a symlink is followed for the check and replaced by the rename, as any editor's save does.
  std::error_code ec;
  const fs::file_status st = fs::status(target_, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw InputError(fmt::format("cannot write '{}': it exists and is not a regular file", target_.string()));
  temp_ = temp_name(target_);
}

AtomicPath::~AtomicPath() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(temp_, ec);
  }
}

void AtomicPath::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec) throw InputError(fmt::format("cannot write '{}': {}", target_.string(), ec.message()));
  committed_ = true;
}

void write_file_atomic(const fs::path& path, std::span<const std::byte> bytes) {
  AtomicPath ap(path);
  std::FILE* f = std::fopen(ap.temp().c_str(), "wb");
  if (!f) throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw InputError(fmt::format("cannot write '{}': write failed", path.string()));
  ap.commit();
}

void write_file_atomic(const fs::path& path, std::string_view text) {
  write_file_atomic(path, std::as_bytes(std::span<const char>(text.data(), text.size())));
}

}  // namespace msh::io

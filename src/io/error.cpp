// The shared range check (io/error.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>

namespace msh {

void require_range(double v, double lo, double hi, const std::string& what) {
  if (!(v >= lo && v <= hi)) throw InputError(fmt::format("{} must be in [{}, {}], got {}", what, lo, hi, v));
}

void require_regular_file(const std::filesystem::path& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symlinks
  if (ec || st.type() == fs::file_type::not_found || st.type() == fs::file_type::regular) return;
  const char* kind = st.type() == fs::file_type::directory ? "a directory"
                     : st.type() == fs::file_type::fifo    ? "a FIFO"
                     : st.type() == fs::file_type::socket  ? "a socket"
                     : st.type() == fs::file_type::block || st.type() == fs::file_type::character
                         ? "a device"
                         : "not a file";
  throw InputError(
      fmt::format("'{}': {}is not a regular file ({}); refused before opening", path.string(), what, kind));
}

}  // namespace msh

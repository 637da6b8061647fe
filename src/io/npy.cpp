// NPY format version 1.0 (numpy/doc/neps/nep-0001-npy-format): '<f4', C order, shape (depth, height, width,
// channels). The reader also accepts versions 2.0/3.0, '<f8', and shapes (H, W, C) and (H, W).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/npy.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string_view>

#include "texture_internal.h"

namespace msh::io::codecs {
namespace fs = std::filesystem;

void write_npy(const fs::path& path, const Volume& v) {
  io::write_npy(path, v.data, v.width, v.height, v.depth, v.channels);
}

}  // namespace msh::io::codecs

namespace msh::io {
namespace fs = std::filesystem;

void write_npy(const fs::path& path, std::span<const float> data, int width, int height, int depth,
               int channels) {
  codecs::validate_values(data, width, height, depth, channels, path);
  std::string header = fmt::format("{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, {}, {}, {}), }}",
                                   depth, height, width, channels);
  // Magic (6) + version (2) + header length (2) + header, padded with spaces and a final '\n' to a multiple
  // of 64 bytes so the data is aligned (what numpy itself writes).
  const std::size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header.push_back('\n');
  std::string head = "\x93NUMPY\x01";
  head.push_back('\0');
  head.push_back(char(header.size() & 0xff));
  head.push_back(char(header.size() >> 8));
  head += header;
  // The header, then the values straight from `data` (no copy), into a temporary renamed when complete.
  AtomicPath ap(path);
  std::FILE* f = std::fopen(ap.temp().c_str(), "wb");
  if (!f) throw InputError(fmt::format("cannot write '{}': {}", path.string(), std::strerror(errno)));
  bool ok = std::fwrite(head.data(), 1, head.size(), f) == head.size();
  ok = ok && std::fwrite(data.data(), sizeof(float), data.size(), f) == data.size();
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw InputError(fmt::format("cannot write '{}': write failed", path.string()));
  ap.commit();
}

}  // namespace msh::io

namespace msh::io::codecs {

namespace {
// Value text of `key` in the header dict (up to the next ',' at depth 0, or the matching ')').
std::string_view dict_value(std::string_view dict, std::string_view key, const fs::path& path) {
  const std::string quoted = fmt::format("'{}'", key);
  const std::size_t k = dict.find(quoted);
  if (k == std::string_view::npos) fail(path, fmt::format("NPY header has no {}", quoted));
  std::size_t i = dict.find(':', k + quoted.size());
  if (i == std::string_view::npos) fail(path, "malformed NPY header");
  ++i;
  while (i < dict.size() && dict[i] == ' ') ++i;
  std::size_t j = i;
  if (j < dict.size() && dict[j] == '(') {
    j = dict.find(')', j);
    if (j == std::string_view::npos) fail(path, "malformed NPY header");
    return dict.substr(i, j + 1 - i);
  }
  while (j < dict.size() && dict[j] != ',' && dict[j] != '}') ++j;
  return dict.substr(i, j - i);
}
}  // namespace

Volume read_npy(const fs::path& path) {
  const std::vector<std::byte> bytes = read_file(path);
  ByteReader r{bytes, &path};
  r.require(0, 10);
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  if (std::string_view(reinterpret_cast<const char*>(b), 6) != "\x93NUMPY")
    fail(path, "not an NPY file (bad magic)");
  const int major = b[6];
  std::size_t header_len, data_start;
  if (major == 1) {
    header_len = b[8] | (std::size_t(b[9]) << 8);
    data_start = 10 + header_len;
  } else if (major == 2 || major == 3) {
    header_len = r.u32(8);
    data_start = 12 + header_len;
  } else {
    fail(path, fmt::format("unsupported NPY version {}", major));
  }
  r.require(data_start - header_len, header_len);
  const std::string_view dict(reinterpret_cast<const char*>(b) + (data_start - header_len), header_len);

  const std::string_view descr = dict_value(dict, "descr", path);
  int elem = 0;
  if (descr == "'<f4'")
    elem = 4;
  else if (descr == "'<f8'")
    elem = 8;
  else
    fail(path, fmt::format("unsupported NPY dtype {} (expected '<f4' or '<f8')", descr));
  if (dict_value(dict, "fortran_order", path) != "False")
    fail(path, "Fortran-order NPY arrays are not supported");

  std::string_view shape = dict_value(dict, "shape", path);
  if (shape.size() < 2 || shape.front() != '(') fail(path, "malformed NPY shape");
  std::vector<long long> dims;
  std::string tuple(shape.substr(1, shape.size() - 2));
  const char* s = tuple.c_str();
  while (*s) {
    while (*s == ' ' || *s == ',') ++s;
    if (!*s) break;
    char* end = nullptr;
    const long long d = std::strtoll(s, &end, 10);
    if (end == s) fail(path, fmt::format("malformed NPY shape {}", shape));
    dims.push_back(d);
    s = end;
  }
  long long D = 1, H, W, C = 1;
  if (dims.size() == 4)
    D = dims[0], H = dims[1], W = dims[2], C = dims[3];
  else if (dims.size() == 3)
    H = dims[0], W = dims[1], C = dims[2];
  else if (dims.size() == 2)
    H = dims[0], W = dims[1];
  else
    fail(path, fmt::format("NPY shape {} must have 2, 3 or 4 axes ((H,W), (H,W,C) or (D,H,W,C))", shape));
  check_dimensions(path, W, H, D, C);

  // Size check before the allocation (docs/formats.md): a 100-byte header must not allocate a 1 GiB volume.
  const std::size_t n = std::size_t(W) * std::size_t(H) * std::size_t(D) * std::size_t(C);
  r.require(data_start, n * elem);
  if (bytes.size() != data_start + n * elem) fail(path, "NPY file size does not match its shape");
  Volume v{int(W), int(H), int(D), int(C)};
  if (elem == 4) {
    std::memcpy(v.data.data(), bytes.data() + data_start, n * 4);
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      double x;
      std::memcpy(&x, bytes.data() + data_start + i * 8, 8);
      v.data[i] = float(x);
    }
  }
  return v;
}

}  // namespace msh::io::codecs

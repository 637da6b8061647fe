// Built by tests/package/consumer_test.cmake with `c++ -std=c++20 ... $(pkg-config --cflags --libs
// microshadow)`: links the static library and its dependencies. Writes and reads back a small NPY volume.
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  msh::io::Volume v(3, 2, 1, 1);
  for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = float(i) / 8;
  msh::io::write_volume(argv[1], v, msh::io::FileFormat::Npy);
  const msh::io::Volume r = msh::io::read_volume(argv[1]);
  const bool ok = r.width == 3 && r.height == 2 && r.channels == 1 && r.data == v.data;
  std::printf("pkg-config library: npy round trip %s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}

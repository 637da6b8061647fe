// libFuzzer target: io::read_texture_level over a DDS or KTX2 file (MSH_FUZZ_EXT ".dds" or ".ktx2"), every
// mip level the file may hold (0, 1, … until the reader says there is no such level; at most 16), as the
// renderer and the three.js loader's C++ reference read a texture's mip chain. The seeds are mip chains in
// every pixel format, BC4 and BC5 included. A Volume or msh::InputError; the Volume of level L must be
// consistent, finite, and no larger than max(1, w0 >> L) × max(1, h0 >> L) for level 0's w0 × h0.
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <algorithm>
#include <cstdlib>

#include "fuzz_common.h"

#ifndef MSH_FUZZ_EXT
#error "define MSH_FUZZ_EXT, \".dds\" or \".ktx2\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = msh::fuzz::input_file("level", MSH_FUZZ_EXT, data, size);
  int w0 = 0, h0 = 0;
  for (int level = 0; level < 16; ++level) {
    try {
      const msh::io::Volume v = msh::io::read_texture_level(path, level);
      msh::fuzz::check_volume(v);
      if (level == 0) {
        w0 = v.width, h0 = v.height;
      } else if (w0 > 0 && (v.width > std::max(1, w0 >> level) || v.height > std::max(1, h0 >> level))) {
        std::abort();  // a level larger than the chain allows
      }
    } catch (const msh::InputError&) {
      if (level > 0) break;  // no such level (or a corrupt one): the levels past it are not read
    }
  }
  return 0;
}

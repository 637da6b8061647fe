// Helpers shared by the texture and material tests.
#pragma once

#include <microshadow/render/scene.h>

namespace msh::test {

// Bit-identical textures: same size, same channel count, every texel equal.
inline bool same(const render::Texture& a, const render::Texture& b) {
  if (a.width() != b.width() || a.height() != b.height() || a.channels() != b.channels()) return false;
  for (int j = 0; j < a.height(); ++j)
    for (int i = 0; i < a.width(); ++i)
      for (int c = 0; c < a.channels(); ++c)
        if (a.at(i, j, c) != b.at(i, j, c)) return false;
  return true;
}

}  // namespace msh::test

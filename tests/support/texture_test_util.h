// Helpers shared by the texture and material tests.
#pragma once

#include <microshadow/render/scene.h>

#include <functional>

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

// A height map from z(x, y) in texel units (z ≤ 0), depth D: h = 1 + z/D.
inline render::Texture depth_field(int w, int h, double depth, const std::function<double(int, int)>& z) {
  render::Texture t(w, h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) t.at(i, j, 0) = float(1.0 + z(i, j) / depth);
  return t;
}

}  // namespace msh::test

// A row-major 2D array of values, row 0 at the top: the renderer's images and the study's planes and masks
// share it. No I/O, no threads.
#pragma once

#include <cstddef>
#include <vector>

namespace msh {

template <class T>
struct Grid {
  int width = 0, height = 0;
  std::vector<T> px;  // width × height, x fastest
  Grid() = default;
  Grid(int w, int h, const T& fill = T()) : width(w), height(h), px(std::size_t(w) * std::size_t(h), fill) {}
  T& at(int x, int y) { return px[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
  const T& at(int x, int y) const { return px[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

}  // namespace msh

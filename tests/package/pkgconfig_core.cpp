// Built by tests/package/consumer_test.cmake with `c++ -std=c++20 $(pkg-config --cflags microshadow-core)`.
#include <microshadow/microshadow.h>

#include <cstdio>

int main() {
  // Chan 2018 at N·L = sqrt(1 − V): the cone's edge, where the term is 1.
  const double t = msh::micro_shadowing::chan_2018(0.75, 0.5);
  std::printf("pkg-config core: chan_2018 %.6f\n", t);
  return t == 1.0 ? 0 : 1;
}

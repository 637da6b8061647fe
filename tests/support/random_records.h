// Test records drawn from one Pcg32 stream, the preamble every shader-input generator shares.
#pragma once

#include <microshadow/math/sampling.h>

#include <cstdint>
#include <vector>

namespace msh::test {

// n records: record i is fill(u, i), where u() is the stream's next uniform double in [0, 1)
// (Pcg32::next_double), so a generator's records depend only on its seed and its order of draws.
template <class R, class Fill>
std::vector<R> random_records(int n, uint64_t seed, Fill fill) {
  Pcg32 rng(seed);
  auto u = [&] { return rng.next_double(); };
  std::vector<R> rs;
  rs.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) rs.push_back(fill(u, i));
  return rs;
}

}  // namespace msh::test

// The exact early-out of the generic micro-shadowing term, the one definition shared by the terms
// (occlusion/micro_shadowing.h), the ALU fits (micro_shadowing_fit.h) and the LUT sampler
// (lut/micro_shadowing_lut.h). Header-only, no dependency beyond math/vec.h, so an engine embedding only the
// LUT sampler pulls in nothing else.
#pragma once

#include <microshadow/math/vec.h>

namespace msh::micro_shadowing {

// A cone normal is within θ of n and of l, so angle(n,l) < 2θ, i.e. N·L > cos 2θ = 1 − 2V
// (docs/theory.md §3). Hence 2V + N·L < 1 ⇒ the generic term is exactly 0, for every roughness and view: no
// samples, no LUT fetch. V and N·L are saturated (NaN → 0).
template <class T>
bool exact_zero(T V, T n_dot_l) {
  return T(2) * saturate(V) + saturate(n_dot_l) < T(1);
}

}  // namespace msh::micro_shadowing

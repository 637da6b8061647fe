// The quadrature module lives in math/quadrature.h; this header keeps the older spellings
// (msh::detail::gauss_kronrod, msh::detail::GaussLegendre) working for code written against them.
#pragma once

#include <microshadow/math/quadrature.h>

namespace msh::detail {
using msh::gauss_kronrod;
using msh::GaussLegendre;
}  // namespace msh::detail

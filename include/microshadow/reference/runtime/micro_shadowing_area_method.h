// Area-light form of every registered micro-shadowing method (occlusion/runtime/micro_shadowing_methods.h):
// the method's point value M(l) = MicroShadowingEvaluator::eval at the query with n_dot_l (and φ) set from
// the direction l, integrated over a light by the exact quadrature of
// reference/micro_shadowing_area_exact.h. A method added to the table gets its area form for free.
// Runtime code (std::function): reference/runtime/, compiled users only. Definitions: docs/area-lights.md.
#pragma once

#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace msh::occlusion {

// The point term of method m at query q as a function of l (local frame, v in the xz plane at azimuth 0, as
// in docs/micro-shadowing.md): n_dot_l = l.z (clamped to [0, 1]); when q.phi is set (and the method accepts
// it) φ = the relative azimuth |atan2(l.y, l.x)| ∈ [0, π], else the method's azimuth mean, which depends on
// l.z only. Breaks: the method's own (MicroShadowingEvaluator::breaks: circles of constant n·l and, with φ,
// curves such as the specular-aware indicator's), else area::standard_z_breaks(V), every circle where a
// built-in term is not smooth.
// The point term type of a registered method (type-erased: the method is chosen at run time).
using AreaPointTerm = area::PointTerm<std::function<double(const Vec3d&)>>;

inline AreaPointTerm area_point_term(const MicroShadowingEvaluator& m, const MicroShadowingQuery& q) {
  const bool uses_phi = q.phi.has_value() && m.info().accepts_phi;
  AreaPointTerm t;
  t.z_only = !uses_phi;
  const MicroShadowingBreaks b = m.breaks(q);
  t.z_breaks = b.known ? b.z : area::standard_z_breaks(q.visibility);
  if (uses_phi)
    for (const MicroShadowingBreaks::Curve& c : b.curves) t.phi_breaks.push_back({c.axis, c.k0, c.k1, c.k2});
  t.M = [&m, q, uses_phi](const Vec3d& l) {
    MicroShadowingQuery p = q;
    p.n_dot_l = std::clamp(l.z, 0.0, 1.0);
    if (uses_phi)
      p.phi = std::min(kPi<double>, std::abs(std::atan2(l.y, l.x)));
    else
      p.phi.reset();
    return m.eval(p);
  };
  return t;
}

// M_area of method m for the light `shape` and the receiver: the exact quadrature. q.n_dot_l and q.phi are
// ignored except through area_point_term (the light's position is in `shape`). A zero-size light gives the
// point value at its centre.
inline double area_micro_shadowing(const MicroShadowingEvaluator& m, const MicroShadowingQuery& q,
                                   const area::Shape& shape, const area::Receiver& receiver,
                                   const area::AreaOptions& opt = {}) {
  return area::area_micro_shadowing_exact(shape, receiver, area_point_term(m, q), opt);
}

}  // namespace msh::occlusion

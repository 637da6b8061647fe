// microshadow.bump_terminator / bump_alpha2: the bump-terminator terms of
// include/microshadow/occlusion/bump_terminator.h (Conty Estevez et al. 2019, Chiang et al. 2019),
// vectorized.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/bump_terminator.h>

#include <algorithm>
#include <cmath>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;

// The CLI's normalization of a direction (scaled by its largest |component| first, so tiny or huge vectors
// normalize exactly as `eval bump-terminator` does); zero and non-finite vectors were refused by broadcast()
// (Domain::Direction), as the CLI refuses them.
Vec3d cli_direction(const Vec3d& v) {
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  return normalize(v / m);
}

}  // namespace

void register_bump(pyb::module_& m) {
  m.def(
      "bump_terminator",
      [](const std::string& method, pyb::handle ng, pyb::handle ns, pyb::handle l, bool hemisphere_test) {
        bump::Method meth{};
        if (!bump::parse_method(method, meth)) throw InputError(fmt::format("unknown --method '{}'", method));
        const auto test = hemisphere_test ? bump::HemisphereTest::kOn : bump::HemisphereTest::kOff;
        const Broadcast b =
            broadcast({{ng, "geometric_normal", 3, Domain::Direction},
                                             {ns, "shading_normal", 3, Domain::Direction},
                                             {l, "light", 3, Domain::Direction}});
        return map_scalar(b, [&](const auto& r, std::size_t i) {
          return bump::term(meth, cli_direction(r.vec(0, i)), cli_direction(r.vec(1, i)),
                            cli_direction(r.vec(2, i)), test);
        });
      },
      "method"_a, "geometric_normal"_a, "shading_normal"_a, "light"_a, "hemisphere_test"_a = false,
      "Bump-terminator shadowing factor, as `microshadow eval bump-terminator` computes it. method: "
      "'conty-2019' (Conty Estevez, Lecocq, Stein 2019, 'A Microfacet-Based Shadowing Function to Solve the "
      "Bump Terminator Problem': Smith GGX G1 of the light about N_g with alpha^2 = tan^2(theta_d)/8), "
      "'chiang-2019' (Chiang, Li, Burley 2019, 'Taming the Shadow Terminator': the cubic of g = "
      "(N_g.L)/((N_s.L)(N_g.N_s))) or 'none' (1). geometric_normal, shading_normal, light: arrays of shape "
      "(..., 3) (any length; normalized as the CLI does), broadcast like numpy ufuncs; float32 in -> "
      "float32 out. hemisphere_test: 0 unless the light is above both hemispheres. A zero or non-finite "
      "vector raises ValueError (as the CLI refuses it). Result in [0, 1].");
  m.def(
      "bump_alpha2",
      [](pyb::handle ng, pyb::handle ns) {
        const Broadcast b = broadcast({{ng, "geometric_normal", 3, Domain::Direction}, {ns, "shading_normal", 3, Domain::Direction}});
        return map_scalar(b, [&](const auto& r, std::size_t i) {
          return bump::alpha2_from_normals(cli_direction(r.vec(0, i)), cli_direction(r.vec(1, i)));
        });
      },
      "geometric_normal"_a, "shading_normal"_a,
      "The GGX roughness alpha^2 = clamp(tan^2(theta_d)/8, 0, 1) that Conty Estevez et al. 2019 assign to "
      "the "
      "perturbation theta_d = angle(N_g, N_s) (listing 12.1); the CLI's 'alpha2'. Shapes as for "
      "bump_terminator.");
}

}  // namespace msh::py

// Glue between the renderer and the other areas' headers: bump-terminator terms and the micro-shadowing LUT.
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/occlusion/bump_terminator.h>

#include "shading_terms.h"

namespace msh::render {

BumpTerminatorTerm::BumpTerminatorTerm(BumpTerminator m) : mode_(m) {}

float BumpTerminatorTerm::eval(const Vec3f& ng, const Vec3f& ns, const Vec3f& l) const {
  switch (mode_) {
    case BumpTerminator::Off:
      return 1.0f;
    case BumpTerminator::Conty2019:
      return bump::conty2019(ng, ns, l);
    case BumpTerminator::Chiang2019:
      return bump::chiang2019(ng, ns, l);
  }
  return 1.0f;
}

class LutSampler {
 public:
  std::shared_ptr<const lut::MicroShadowingLut> table;
  lut::MicroShadowingLutView view;
  bool two_d = false;
};

std::shared_ptr<const LutSampler> load_lut_sampler(const std::string& path, bool two_d) {
  auto s = std::make_shared<LutSampler>();
  s->two_d = two_d;
  // No file: the LUT module's default table (cone layout, 3D or N·V = 1, baked once per process and cached).
  s->table = path.empty()
                 ? lut::default_micro_shadowing_lut(two_d)
                 : std::make_shared<const lut::MicroShadowingLut>(lut::load_micro_shadowing_lut(path));
  s->view = s->table->view();
  return s;
}

// The 2D LUT is the N·V = 1 slice (Zurita 2026): N·V is not looked up. Any layout (the view dispatches); an
// azimuth-aware table is evaluated at the light's azimuth, never reduced to its mean silently.
float sample_lut(const LutSampler& l, float V, float n_dot_l, float n_dot_v, float roughness, float cos_phi) {
  const float nv = l.two_d ? 1.0f : n_dot_v;
  if (l.view.harmonics > 0)
    return lut::sample_micro_shadowing_azimuth(l.view, V, n_dot_l, nv, roughness, cos_phi);
  return lut::sample_micro_shadowing(l.view, V, n_dot_l, nv, roughness);
}

}  // namespace msh::render

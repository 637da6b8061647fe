// Glue between the renderer and the other areas' headers: bump-terminator terms and the micro-shadowing LUT.
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

class LutSampler {};

std::shared_ptr<const LutSampler> load_lut_sampler(const std::string&, bool) {
  throw InputError("the micro-shadowing LUT methods are not available yet (the LUT module has not landed)");
}
float sample_lut(const LutSampler&, float, float, float, float) { return 1.0f; }

}  // namespace msh::render

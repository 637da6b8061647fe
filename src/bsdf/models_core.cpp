#include <microshadow/bsdf/brdf_model.h>
// Filled by the BRDF-models work (issue 6): specular, Fresnel, multiple bounce, diffuse.
namespace msh::bsdf {
std::vector<ModelInfo> core_brdf_models() { return {}; }
}  // namespace msh::bsdf

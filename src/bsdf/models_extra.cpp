#include <microshadow/bsdf/brdf_model.h>
// Filled by the BRDF-models work (issue 6): cloth, thin film, layered.
namespace msh::bsdf {
std::vector<ModelInfo> extra_brdf_models() { return {}; }
}  // namespace msh::bsdf

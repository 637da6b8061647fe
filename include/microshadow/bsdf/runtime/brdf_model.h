// Runtime (double precision) interface to every BRDF model, for the CLI (`eval brdf`, `plot brdf`) and the
// white-furnace and reciprocity tests: a registry of models by name (std::function, std::map) over
// virtual BrdfModel instances. Not engine code: the math itself lives in the header-only templates of
// include/microshadow/bsdf/ (this directory's parent); a BrdfModel wraps one configured instance.
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace msh::bsdf {

struct BsdfSample {
  Vec3d wi;   // sampled incident (light) direction, local frame
  Rgbd f;     // BRDF value f(wo, wi), no cosine
  double pdf; // solid-angle pdf of wi
};

class BrdfModel {
 public:
  virtual ~BrdfModel() = default;
  // f(wo, wi): the BRDF (without the cosine), local shading frame, n = +z. Zero below the horizon of either
  // direction unless the model says otherwise. Finite for every unit input.
  virtual Rgbd f(const Vec3d& wo, const Vec3d& wi) const = 0;
  // Importance sampling of wi given wo. Default: cosine-weighted hemisphere.
  virtual std::optional<BsdfSample> sample(const Vec3d& wo, Vec2d u) const;
  virtual double pdf(const Vec3d& wo, const Vec3d& wi) const;
  // Whether f(wo, wi) = f(wi, wo) is claimed (tests check it where true).
  virtual bool reciprocal() const { return true; }
  // Whether the model claims energy conservation (albedo ≤ 1) for every parameter value.
  virtual bool energy_conserving() const { return true; }
};

// A model parameter as the CLI exposes it (`--name value`, or `--name R,G,B` when components == 3).
struct ParamSpec {
  std::string name;  // CLI spelling without dashes, e.g. "roughness", "base-color"
  std::string help;
  std::vector<double> def;  // default value(s); size == components
  double lo = 0.0, hi = 1.0;
  int components = 1;
  // Non-empty: an enumerated parameter. The CLI takes one of these names (`--fresnel schlick`) and stores its
  // index as the value; lo = 0 and hi = choices.size() − 1.
  std::vector<std::string> choices;
};

// Values by ParamSpec name; missing names take the spec default (ModelInfo::make receives a complete map).
struct BrdfParams {
  std::map<std::string, std::vector<double>> values;
  double get(const std::string& name) const;  // throws std::out_of_range naming the parameter
  Rgbd rgb(const std::string& name) const;
};

struct ModelInfo {
  std::string name;     // e.g. "ggx", "lambert", "disney-diffuse"
  std::string summary;  // one line
  std::string source;   // paper / RTR4 equation numbers
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<BrdfModel>(const BrdfParams&)> make;
};

// Every model: core_brdf_models() then extra_brdf_models(), in that order.
const std::vector<ModelInfo>& brdf_models();
// Throws msh::InputError for an unknown name (the message lists the known ones).
const ModelInfo& find_brdf_model(const std::string& name);
// Fills defaults and range-checks; throws msh::InputError naming the parameter on bad values.
BrdfParams complete_params(const ModelInfo& info, const BrdfParams& given);

// find_brdf_model + complete_params + make: a configured model from a name and (partial) parameter values.
// Throws msh::InputError on an unknown name or bad values.
std::unique_ptr<BrdfModel> make_brdf(const std::string& name,
                                     const std::map<std::string, std::vector<double>>& values = {});

// Specular, Fresnel, multiple-bounce and diffuse models (src/bsdf/models_core.cpp).
std::vector<ModelInfo> core_brdf_models();
// Cloth, thin film and layered models (src/bsdf/models_extra.cpp).
std::vector<ModelInfo> extra_brdf_models();

}  // namespace msh::bsdf

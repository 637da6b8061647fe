#include <fmt/format.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>

#include <stdexcept>

namespace msh::bsdf {

std::optional<BsdfSample> BrdfModel::sample(const Vec3d& wo, Vec2d u) const {
  const Vec3d wi = sample_cosine_hemisphere(u);
  const double pdf = cosine_hemisphere_pdf(wi.z);
  if (!(pdf > 0.0)) return std::nullopt;
  return BsdfSample{wi, f(wo, wi), pdf};
}

double BrdfModel::pdf(const Vec3d&, const Vec3d& wi) const { return cosine_hemisphere_pdf(wi.z); }

double BrdfParams::get(const std::string& name) const {
  auto it = values.find(name);
  if (it == values.end() || it->second.empty()) throw std::out_of_range("missing BRDF parameter " + name);
  return it->second[0];
}

Rgbd BrdfParams::rgb(const std::string& name) const {
  auto it = values.find(name);
  if (it == values.end() || it->second.empty()) throw std::out_of_range("missing BRDF parameter " + name);
  const auto& v = it->second;
  return v.size() >= 3 ? Rgbd(v[0], v[1], v[2]) : Rgbd(v[0]);
}

const std::vector<ModelInfo>& brdf_models() {
  static const std::vector<ModelInfo> all = [] {
    std::vector<ModelInfo> m = core_brdf_models();
    for (auto& x : extra_brdf_models()) m.push_back(std::move(x));
    return m;
  }();
  return all;
}

const ModelInfo& find_brdf_model(const std::string& name) {
  std::string known;
  for (const auto& m : brdf_models()) {
    if (m.name == name) return m;
    known += (known.empty() ? "" : ", ") + m.name;
  }
  throw InputError(fmt::format("unknown BRDF model '{}' (known: {})", name, known));
}

BrdfParams complete_params(const ModelInfo& info, const BrdfParams& given) {
  BrdfParams out;
  for (const auto& spec : info.params) {
    auto it = given.values.find(spec.name);
    std::vector<double> v = it == given.values.end() ? spec.def : it->second;
    if (v.size() == 1 && spec.components == 3) v = {v[0], v[0], v[0]};
    if (int(v.size()) != spec.components)
      throw InputError(fmt::format("--{} takes {} value(s), got {}", spec.name, spec.components, v.size()));
    for (double x : v) require_range(x, spec.lo, spec.hi, "--" + spec.name);
    out.values[spec.name] = v;
  }
  for (const auto& [name, v] : given.values) {
    bool known = false;
    for (const auto& spec : info.params) known |= spec.name == name;
    if (!known) throw InputError(fmt::format("model '{}' has no parameter --{}", info.name, name));
  }
  return out;
}

std::unique_ptr<BrdfModel> make_brdf(const std::string& name,
                                     const std::map<std::string, std::vector<double>>& values) {
  const ModelInfo& info = find_brdf_model(name);
  BrdfParams given;
  given.values = values;
  return info.make(complete_params(info, given));
}

}  // namespace msh::bsdf

// Runtime wrappers (double precision) of the specular, Fresnel, multiple-bounce and diffuse models of
// include/microshadow/bsdf/{fresnel,specular,multiscatter,diffuse}.h, for `eval brdf`, the tests and the
// renderer. Every model lists its source equation (RTR4 numbering) and its parameters with ranges.
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/beckmann.h>

namespace msh::bsdf {

namespace {

// ---- Sampling shared by the models with a diffuse and a GGX specular lobe: with probability q a
// cosine-weighted direction, otherwise the visible-normal sample (u.x rescaled into the chosen lobe); the
// sample's pdf is the model's mixture pdf. Empty where the specular sample is or the pdf is 0.
template <class Model>
std::optional<BsdfSample> sample_lobes(const Model& model, const GGX<double>& ggx, const Vec3d& wo, Vec2d u,
                                       double q) {
  Vec3d wi;
  if (u.x < q) {
    wi = sample_cosine_hemisphere(Vec2d(std::min(u.x / q, kOneMinusEpsilon<double>), u.y));
  } else {
    const auto s = sample_microfacet_specular(
        ggx, wo, Vec2d(std::min((u.x - q) / (1 - q), kOneMinusEpsilon<double>), u.y));
    if (!s) return std::nullopt;
    wi = s->wi;
  }
  const double p = model.pdf(wo, wi);
  if (!(p > 0)) return std::nullopt;
  return BsdfSample{wi, model.f(wo, wi), p};
}

// ---- Fresnel choice shared by the specular models.

enum class FresnelKind { None, Schlick, SchlickGeneralized, Dielectric, Conductor };
const std::vector<std::string> kFresnelNames = {"none", "schlick", "schlick-generalized", "dielectric",
                                                "conductor"};

struct FresnelSpec {
  FresnelKind kind = FresnelKind::Schlick;
  Rgbd f0{0.04}, f90{1.0}, eta{1.0}, k{0.0};
  double p = 0.2, ior = 1.5;
  Rgbd avg{1.0};

  static FresnelSpec from(const BrdfParams& P) {
    FresnelSpec s;
    s.kind = FresnelKind(int(P.get("fresnel")));
    s.f0 = P.rgb("f0");
    s.f90 = P.rgb("f90");
    s.p = P.get("p");
    s.ior = P.get("ior");
    s.eta = P.rgb("eta");
    s.k = P.rgb("k");
    switch (s.kind) {
      case FresnelKind::None:
        s.avg = Rgbd(1.0);
        break;
      case FresnelKind::Schlick:
        s.avg = fresnel_average_schlick<double>(s.f0);
        break;
      case FresnelKind::SchlickGeneralized:
        s.avg = fresnel_average_schlick_generalized(s.f0, s.f90, s.p);
        break;
      case FresnelKind::Dielectric:
        s.avg = Rgbd(fresnel_average_dielectric(s.ior));
        break;
      case FresnelKind::Conductor:
        s.avg = {fresnel_average_conductor(s.eta.r, s.k.r), fresnel_average_conductor(s.eta.g, s.k.g),
                 fresnel_average_conductor(s.eta.b, s.k.b)};
        break;
    }
    return s;
  }
  Rgbd operator()(double c) const {
    switch (kind) {
      case FresnelKind::None:
        return Rgbd(1.0);
      case FresnelKind::Schlick:
        return fresnel_schlick(f0, c);
      case FresnelKind::SchlickGeneralized:
        return fresnel_schlick_generalized(f0, f90, p, c);
      case FresnelKind::Dielectric:
        return Rgbd(fresnel_dielectric(c, ior));
      case FresnelKind::Conductor:
        return fresnel_conductor(c, eta, k);
    }
    return Rgbd(1.0);
  }
};

std::vector<ParamSpec> fresnel_params(const std::string& def_kind = "schlick") {
  double def = 1;
  for (size_t i = 0; i < kFresnelNames.size(); ++i)
    if (kFresnelNames[i] == def_kind) def = double(i);
  return {
      {"fresnel",
       "Fresnel term: none (F = 1), schlick (9.16), schlick-generalized (9.18), dielectric, conductor",
       {def},
       0,
       double(kFresnelNames.size() - 1),
       1,
       kFresnelNames},
      {"f0", "Normal-incidence reflectance F0 (schlick, schlick-generalized)", {0.04}, 0, 1, 3, {}},
      {"f90", "Grazing reflectance F90 (schlick-generalized)", {1.0}, 0, 1, 3, {}},
      {"p",
       "Exponent p of the generalized Schlick form, F90 weight (1 - cos)^(1/p); 0.2 = Schlick",
       {0.2},
       0.01,
       100,
       1,
       {}},
      {"ior", "Relative index of refraction (dielectric)", {1.5}, 1, 5, 1, {}},
      {"eta",
       "Conductor IOR, real part per channel (default: gold, Rec.709 approx.)",
       {0.143, 0.374, 1.442},
       0.01,
       20,
       3,
       {}},
      {"k", "Conductor IOR, imaginary part per channel (default: gold)", {3.983, 2.385, 1.603}, 0, 20, 3, {}},
  };
}

ParamSpec roughness_param(const std::string& name = "roughness", double def = 0.5) {
  return {name, "Perceptual roughness r (alpha = r^2)", {def}, 0, 1, 1, {}};
}
ParamSpec albedo_param(const std::string& name = "rho", double def = 0.8) {
  return {name, "Subsurface albedo rho_ss (diffuse colour)", {def}, 0, 1, 3, {}};
}
ParamSpec onoff_param(const std::string& name, const std::string& help, bool def) {
  return {name, help, {def ? 1.0 : 0.0}, 0, 1, 1, {"off", "on"}};
}

std::vector<ParamSpec> concat(std::vector<ParamSpec> a, const std::vector<ParamSpec>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// ---- GGX specular (9.34) with optional Kulla-Conty multiple bounce (9.56).

class GgxSpecular final : public BrdfModel {
 public:
  GgxSpecular(double r, double aniso, FresnelSpec fr, G2Form g2, bool ms)
      : r_(r), ggx_(ggx_imageworks_aniso(r, aniso)), fr_(std::move(fr)), g2_(g2), ms_(ms) {}

  Rgbd f(const Vec3d& wo, const Vec3d& wi) const override {
    const auto e = microfacet_specular(ggx_, wo, wi, g2_);
    Rgbd v = fr_(e.cos_hl) * e.f1;
    if (ms_) v += ggx_multiscatter(fr_.avg, r_, wi, wo);
    return v;
  }
  std::optional<BsdfSample> sample(const Vec3d& wo, Vec2d u) const override {
    if (!(wo.z > 0)) return std::nullopt;
    return sample_lobes(*this, ggx_, wo, u, ms_q(wo));
  }
  double pdf(const Vec3d& wo, const Vec3d& wi) const override {
    const double q = ms_q(wo);
    return (1 - q) * microfacet_specular_pdf(ggx_, wo, wi) + q * cosine_hemisphere_pdf(wi.z);
  }

 private:
  // Probability of sampling the (cosine-like) multiple-bounce lobe: its share 1 − E(μ), bounded.
  double ms_q(const Vec3d& wo) const { return ms_ ? clamp(1.0 - ggx_E(wo.z, r_), 0.02, 0.5) : 0.0; }
  double r_;
  GGX<double> ggx_;
  FresnelSpec fr_;
  G2Form g2_;
  bool ms_;
};

// One VNDF-sampled microfacet specular lobe (9.34) over any Smith NDF: Beckmann (9.35/9.52 with the exact Λ
// 9.38) and the two-GGX mixture (Imageworks).
template <class Ndf>
class MicrofacetLobe final : public BrdfModel {
 public:
  MicrofacetLobe(Ndf ndf, FresnelSpec fr, G2Form g2) : ndf_(std::move(ndf)), fr_(std::move(fr)), g2_(g2) {}
  Rgbd f(const Vec3d& wo, const Vec3d& wi) const override {
    const auto e = microfacet_specular(ndf_, wo, wi, g2_);
    return fr_(e.cos_hl) * e.f1;
  }
  std::optional<BsdfSample> sample(const Vec3d& wo, Vec2d u) const override {
    const auto s = sample_microfacet_specular(ndf_, wo, u, g2_);
    if (!s) return std::nullopt;
    return BsdfSample{s->wi, f(wo, s->wi), s->pdf};
  }
  double pdf(const Vec3d& wo, const Vec3d& wi) const override {
    return microfacet_specular_pdf(ndf_, wo, wi);
  }

 private:
  Ndf ndf_;
  FresnelSpec fr_;
  G2Form g2_;
};

// A diffuse model given as a lambda, sampled with the default cosine sampler.
class DiffuseModel final : public BrdfModel {
 public:
  using Fn = std::function<Rgbd(const Vec3d&, const Vec3d&)>;
  DiffuseModel(Fn f, bool reciprocal, bool conserving)
      : f_(std::move(f)), reciprocal_(reciprocal), conserving_(conserving) {}
  Rgbd f(const Vec3d& wo, const Vec3d& wi) const override { return f_(wi, wo); }
  bool reciprocal() const override { return reciprocal_; }
  bool energy_conserving() const override { return conserving_; }

 private:
  Fn f_;
  bool reciprocal_, conserving_;
};

// GGX specular (Schlick F0, optional multiple bounce) plus a diffuse term: Lambert (RTR4 fig. 9.41 rows 1, 3)
// or the KSK coupled diffuse (9.65; rows 2, 4) whose R_spec is this very specular term.
class SpecularPlusDiffuse final : public BrdfModel {
 public:
  SpecularPlusDiffuse(double r, Rgbd f0, bool ms, Rgbd albedo, bool ksk)
      : r_(r), ggx_(roughness_to_alpha(r)), f0_(f0), ms_(ms), albedo_(albedo), ksk_(ksk) {
    favg_ = fresnel_average_schlick<double>(f0);
    ravg_ = ggx_albedo_schlick_avg(f0_, r_);
    if (ms_) ravg_ += ms_fresnel_factor(favg_, ggx_E_avg(r_)) * (1.0 - ggx_E_avg(r_));
    const double wd = max_component(albedo_), ws = max_component(ggx_albedo_schlick(f0_, 1.0, r_));
    q_ = wd + ws > 0 ? clamp(wd / (wd + ws), 0.1, 0.9) : 0.5;
  }
  const Rgbd& ravg() const { return ravg_; }
  // R_spec(μ): single-scattering albedo (shipped DFG table) plus the multiple-bounce lobe's albedo.
  Rgbd spec_albedo(double mu) const {
    Rgbd a = ggx_albedo_schlick(f0_, mu, r_);
    if (ms_) a += ggx_multiscatter_albedo(favg_, r_, mu);
    return a;
  }
  Rgbd f(const Vec3d& wo, const Vec3d& wi) const override {
    if (!(wo.z > 0) || !(wi.z > 0)) return Rgbd(0.0);
    const auto e = microfacet_specular(ggx_, wo, wi);
    Rgbd v = fresnel_schlick(f0_, e.cos_hl) * e.f1;
    if (ms_) v += ggx_multiscatter(favg_, r_, wi, wo);
    if (ksk_)
      v += diffuse_ksk(albedo_, spec_albedo(wi.z), spec_albedo(wo.z), ravg_, wi, wo);
    else
      v += diffuse_lambert(albedo_, wi, wo);
    return v;
  }
  std::optional<BsdfSample> sample(const Vec3d& wo, Vec2d u) const override {
    if (!(wo.z > 0)) return std::nullopt;
    return sample_lobes(*this, ggx_, wo, u, q_);
  }
  double pdf(const Vec3d& wo, const Vec3d& wi) const override {
    return (1 - q_) * microfacet_specular_pdf(ggx_, wo, wi) + q_ * cosine_hemisphere_pdf(wi.z);
  }
  bool energy_conserving() const override { return ksk_; }

 private:
  double r_;
  GGX<double> ggx_;
  Rgbd f0_;
  bool ms_;
  Rgbd albedo_;
  bool ksk_;
  Rgbd favg_, ravg_;
  double q_;
};

ModelInfo diffuse_info(std::string name, std::string summary, std::string source,
                       std::vector<ParamSpec> params,
                       std::function<DiffuseModel::Fn(const BrdfParams&)> make_fn, bool reciprocal,
                       bool conserving) {
  ModelInfo m;
  m.name = std::move(name);
  m.summary = std::move(summary);
  m.source = std::move(source);
  m.params = std::move(params);
  m.make = [make_fn, reciprocal, conserving](const BrdfParams& P) -> std::unique_ptr<BrdfModel> {
    return std::make_unique<DiffuseModel>(make_fn(P), reciprocal, conserving);
  };
  return m;
}

ParamSpec f0_param() {
  return {"f0", "Specular normal-incidence reflectance F0 (Schlick)", {0.04}, 0, 1, 3, {}};
}

// Oren & Nayar 1994 (RTR4 §9.9.4), full or qualitative: rho and the slope-angle deviation sigma.
using OrenNayarDiffuse = Rgbd (*)(const Rgbd&, double, const Vec3d&, const Vec3d&);
ModelInfo oren_nayar_info(std::string name, std::string summary, OrenNayarDiffuse fn) {
  const ParamSpec sigma{
      "sigma", "Oren-Nayar slope-angle standard deviation sigma (radians)", {0.5}, 0, 1.5707963267948966, 1,
      {}};
  return diffuse_info(
      std::move(name), std::move(summary), "Oren & Nayar 1994 (RTR4 §9.9.4)", {albedo_param(), sigma},
      [fn](const BrdfParams& P) -> DiffuseModel::Fn {
        const Rgbd a = P.rgb("rho");
        const double s = P.get("sigma");
        return [a, s, fn](const Vec3d& l, const Vec3d& v) { return fn(a, s, l, v); };
      },
      true, false);
}

// An energy-conserving diffuse term of (rho, f0) coupled to a Schlick specular: 9.62, 9.63, 9.64.
using RhoF0Diffuse = Rgbd (*)(const Rgbd&, const Rgbd&, const Vec3d&, const Vec3d&);
ModelInfo rho_f0_diffuse_info(std::string name, std::string summary, std::string source, RhoF0Diffuse fn,
                              bool reciprocal) {
  return diffuse_info(
      std::move(name), std::move(summary), std::move(source), {albedo_param(), f0_param()},
      [fn](const BrdfParams& P) -> DiffuseModel::Fn {
        const Rgbd a = P.rgb("rho"), f0 = P.rgb("f0");
        return [a, f0, fn](const Vec3d& l, const Vec3d& v) { return fn(a, f0, l, v); };
      },
      reciprocal, true);
}

}  // namespace

std::vector<ModelInfo> core_brdf_models() {
  std::vector<ModelInfo> v;
  const std::vector<std::string> g2_names = {"height-correlated", "separable"};

  v.push_back(
      {"ggx", "GGX microfacet specular, optional Kulla-Conty multiple-bounce lobe",
       "RTR4 9.34 + 9.41/9.53 (GGX) + 9.31/9.27 (Smith G2) + 9.55 (aniso) + 9.56-9.59 (multiple bounce); "
       "Walter et al. 2007, Kulla & Conty 2017",
       concat({roughness_param(),
               {"anisotropy",
                "Imageworks anisotropy k (9.55): ax = r^2(1+k), ay = r^2(1-k)",
                {0.0},
                -1,
                1,
                1,
                {}},
               {"g2", "Smith masking-shadowing form", {0}, 0, 1, 1, g2_names},
               onoff_param("multiscatter", "Add the Kulla-Conty multiple-bounce lobe (9.56)", false)},
              fresnel_params()),
       [](const BrdfParams& P) -> std::unique_ptr<BrdfModel> {
         return std::make_unique<GgxSpecular>(P.get("roughness"), P.get("anisotropy"), FresnelSpec::from(P),
                                              G2Form(int(P.get("g2"))), P.get("multiscatter") > 0.5);
       }});

  v.push_back(
      {"beckmann", "Beckmann microfacet specular (exact Smith Lambda), VNDF-sampled",
       "RTR4 9.34 + 9.35/9.52 (Beckmann) + 9.38 (Lambda) + 9.31/9.27; Walter et al. 2007",
       concat({roughness_param(),
               {"anisotropy", "Anisotropy k (9.55 form): ax = r^2(1+k), ay = r^2(1-k)", {0.0}, -1, 1, 1, {}},
               {"g2", "Smith masking-shadowing form", {0}, 0, 1, 1, g2_names}},
              fresnel_params()),
       [](const BrdfParams& P) -> std::unique_ptr<BrdfModel> {
         const double r = P.get("roughness"), aniso = P.get("anisotropy");
         return std::make_unique<MicrofacetLobe<Beckmann<double>>>(
             Beckmann<double>(r * r * (1 + aniso), r * r * (1 - aniso)), FresnelSpec::from(P),
             G2Form(int(P.get("g2"))));
       }});

  v.push_back(
      {"ggx-dual", "Two-lobe GGX specular: a blend of two GGX NDFs as one extended NDF (Imageworks)",
       "RTR4 §9.8.1 (multiple lobes) + 9.34; Kulla & Conty 2017; Smith Λ of the mixture = mixture of Λ",
       concat({roughness_param(),
               roughness_param("roughness2", 0.8),
               {"mix", "Weight w of the second NDF: D = (1-w) D1 + w D2", {0.3}, 0, 1, 1, {}}},
              fresnel_params()),
       [](const BrdfParams& P) -> std::unique_ptr<BrdfModel> {
         return std::make_unique<MicrofacetLobe<GGXMixture<double>>>(
             GGXMixture<double>(GGX<double>(roughness_to_alpha(P.get("roughness"))),
                                GGX<double>(roughness_to_alpha(P.get("roughness2"))), P.get("mix")),
             FresnelSpec::from(P), G2Form::HeightCorrelated);
       }});

  v.push_back(diffuse_info(
      "lambert", "Lambertian diffuse rho/pi", "RTR4 9.61", {albedo_param()},
      [](const BrdfParams& P) -> DiffuseModel::Fn {
        const Rgbd a = P.rgb("rho");
        return [a](const Vec3d& l, const Vec3d& v) { return diffuse_lambert(a, l, v); };
      },
      true, true));
  v.push_back(rho_f0_diffuse_info(
      "lambert-fresnel-n", "(1 - F(n,l)) rho/pi: diffuse coupled to a flat Schlick mirror (not reciprocal)",
      "RTR4 9.62", &diffuse_fresnel_n<double, Rgbd>, false));
  v.push_back(rho_f0_diffuse_info("lambert-fresnel-h",
                                  "(1 - F(h,l)) rho/pi: diffuse coupled to a microfacet specular term",
                                  "RTR4 9.63", &diffuse_fresnel_h<double, Rgbd>, true));
  v.push_back(rho_f0_diffuse_info("shirley", "Shirley et al. 1997 coupled diffuse for a flat Schlick mirror",
                                  "RTR4 9.64", &diffuse_shirley<double, Rgbd>, true));
  v.push_back(diffuse_info(
      "ksk", "Kelemen/Szirmay-Kalos coupled diffuse for a GGX Schlick specular (diffuse term only)",
      "RTR4 9.65; Ashikhmin & Shirley 2000, Kelemen & Szirmay-Kalos 2001; R_spec from the shipped DFG table",
      {albedo_param(), roughness_param(), f0_param(),
       onoff_param("multiscatter", "Include the Kulla-Conty lobe in R_spec", false)},
      [](const BrdfParams& P) -> DiffuseModel::Fn {
        auto full = std::make_shared<SpecularPlusDiffuse>(P.get("roughness"), P.rgb("f0"),
                                                          P.get("multiscatter") > 0.5, P.rgb("rho"), true);
        const Rgbd a = P.rgb("rho");
        return [full, a](const Vec3d& l, const Vec3d& v) {
          if (!(l.z > 0) || !(v.z > 0)) return Rgbd(0.0);
          return diffuse_ksk(a, full->spec_albedo(l.z), full->spec_albedo(v.z), full->ravg(), l, v);
        };
      },
      true, true));
  v.push_back(diffuse_info(
      "disney-diffuse", "Disney (Burley 2012) diffuse with the subsurface term",
      "RTR4 9.66-9.67; Burley 2012",
      {albedo_param("base-color"),
       roughness_param(),
       {"subsurface", "Subsurface blend k_ss", {0.0}, 0, 1, 1, {}}},
      [](const BrdfParams& P) -> DiffuseModel::Fn {
        const Rgbd a = P.rgb("base-color");
        const double r = P.get("roughness"), k = P.get("subsurface");
        return [a, r, k](const Vec3d& l, const Vec3d& v) { return diffuse_disney(a, r, k, l, v); };
      },
      true, false));
  v.push_back(diffuse_info(
      "hammon", "Hammon 2017 diffuse for GGX + height-correlated Smith microsurfaces",
      "RTR4 9.68-9.69; Hammon 2017", {albedo_param(), roughness_param(), f0_param()},
      [](const BrdfParams& P) -> DiffuseModel::Fn {
        const Rgbd a = P.rgb("rho"), f0 = P.rgb("f0");
        const double alpha = roughness_to_alpha(P.get("roughness"));
        return [a, f0, alpha](const Vec3d& l, const Vec3d& v) { return diffuse_hammon(a, alpha, f0, l, v); };
      },
      true, false));
  v.push_back(oren_nayar_info("oren-nayar", "Oren-Nayar 1994, full model with interreflection",
                              &diffuse_oren_nayar<double, Rgbd>));
  v.push_back(oren_nayar_info("oren-nayar-qualitative", "Oren-Nayar 1994 qualitative model",
                              &diffuse_oren_nayar_qualitative<double, Rgbd>));

  for (const bool ksk : {false, true}) {
    v.push_back({ksk ? "ggx-ksk" : "ggx-lambert",
                 ksk ? "GGX specular (Schlick) + Kelemen/Szirmay-Kalos coupled diffuse: energy conserving"
                     : "GGX specular (Schlick) + Lambert diffuse (uncoupled: may exceed 1)",
                 ksk ? "RTR4 9.34 + 9.65 (fig. 9.41 rows 2, 4)" : "RTR4 9.34 + 9.61 (fig. 9.41 rows 1, 3)",
                 {albedo_param(), roughness_param(), f0_param(),
                  onoff_param("multiscatter", "Add the Kulla-Conty multiple-bounce lobe (9.56)", false)},
                 [ksk](const BrdfParams& P) -> std::unique_ptr<BrdfModel> {
                   return std::make_unique<SpecularPlusDiffuse>(
                       P.get("roughness"), P.rgb("f0"), P.get("multiscatter") > 0.5, P.rgb("rho"), ksk);
                 }});
  }
  return v;
}

}  // namespace msh::bsdf

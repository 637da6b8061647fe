// Cloth, thin-film and layered BRDF models for the runtime registry (`eval brdf --model
// NAME`). The math lives in include/microshadow/bsdf/{cloth,thin_film,layered}.h; these wrappers only
// configure it and add importance sampling (mixtures of the cosine lobe and the model's own NDF / VNDF
// sampler).
#include <microshadow/bsdf/cloth.h>
#include <microshadow/bsdf/layered.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/bsdf/thin_film.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>

namespace msh::bsdf {

namespace {

using Factory = std::function<std::unique_ptr<BrdfModel>(const BrdfParams&)>;

// A one-lobe or mixture sampler built from parts: each component samples wi and reports its own pdf.
struct Lobe {
  double weight;
  std::function<std::optional<Vec3d>(const Vec3d& wo, Vec2d u)> sample;
  std::function<double(const Vec3d& wo, const Vec3d& wi)> pdf;
};

Lobe cosine_lobe(double w) {
  return {w, [](const Vec3d&, Vec2d u) { return std::optional<Vec3d>(sample_cosine_hemisphere(u)); },
          [](const Vec3d&, const Vec3d& wi) { return cosine_hemisphere_pdf(wi.z); }};
}

// Reflection about a microfacet normal sampled with pdf_m(m): pdf(wi) = pdf_m(m) / (4 |wo·m|), m = h(wo, wi).
template <class SampleM, class PdfM>
Lobe reflect_lobe(double w, SampleM sm, PdfM pm) {
  return {w,
          [sm](const Vec3d& wo, Vec2d u) -> std::optional<Vec3d> {
            const Vec3d m = sm(wo, u);
            const double d = dot(wo, m);
            if (!(d > 0)) return std::nullopt;
            const Vec3d wi = reflect(wo, m);
            if (!(wi.z > 0)) return std::nullopt;
            return wi;
          },
          [pm](const Vec3d& wo, const Vec3d& wi) {
            if (!(wi.z > 0 && wo.z > 0)) return 0.0;
            const Vec3d m = normalize(wo + wi);
            const double d = dot(wo, m);
            return d > 0 ? pm(wo, m) / (4.0 * d) : 0.0;
          }};
}

// Half cosine-weighted, half reflection about a normal sampled from the cloth NDF (its own
// sample_ndf/pdf_ndf).
template <class Ndf>
std::vector<Lobe> cosine_and_ndf_lobes(const Ndf& ndf) {
  return {cosine_lobe(0.5), reflect_lobe(
                                0.5, [ndf](const Vec3d&, Vec2d u) { return ndf.sample_ndf(u); },
                                [ndf](const Vec3d&, const Vec3d& mm) { return ndf.pdf_ndf(mm); })};
}

class LambdaModel : public BrdfModel {
 public:
  using F = std::function<Rgbd(const Vec3d&, const Vec3d&)>;
  LambdaModel(F f, std::vector<Lobe> lobes, bool reciprocal, bool energy)
      : f_(std::move(f)), lobes_(std::move(lobes)), reciprocal_(reciprocal), energy_(energy) {
    double s = 0;
    for (const auto& l : lobes_) s += l.weight;
    for (auto& l : lobes_) l.weight /= s;
  }
  Rgbd f(const Vec3d& wo, const Vec3d& wi) const override { return f_(wo, wi); }
  std::optional<BsdfSample> sample(const Vec3d& wo, Vec2d u) const override {
    if (!(wo.z > 0)) return std::nullopt;
    // Pick the component with u.x and rescale it to [0,1) for the component's own warp.
    double acc = 0;
    size_t k = 0;
    for (; k + 1 < lobes_.size(); ++k) {
      if (u.x < acc + lobes_[k].weight) break;
      acc += lobes_[k].weight;
    }
    const double ux = std::min((u.x - acc) / lobes_[k].weight, kOneMinusEpsilon<double>);
    const auto wi = lobes_[k].sample(wo, Vec2d(std::max(ux, 0.0), u.y));
    if (!wi || !(wi->z > 0)) return std::nullopt;
    const double p = pdf(wo, *wi);
    if (!(p > 0)) return std::nullopt;
    return BsdfSample{*wi, f(wo, *wi), p};
  }
  double pdf(const Vec3d& wo, const Vec3d& wi) const override {
    if (!(wo.z > 0 && wi.z > 0)) return 0.0;
    double p = 0;
    for (const auto& l : lobes_) p += l.weight * l.pdf(wo, wi);
    return p;
  }
  bool reciprocal() const override { return reciprocal_; }
  bool energy_conserving() const override { return energy_; }

 private:
  F f_;
  std::vector<Lobe> lobes_;
  bool reciprocal_, energy_;
};

ParamSpec make_param(const std::string& name, const std::string& help, std::vector<double> def, double lo,
                     double hi) {
  ParamSpec p;
  p.name = name, p.help = help, p.def = std::move(def), p.lo = lo, p.hi = hi;
  p.components = int(p.def.size());
  return p;
}
ParamSpec rgb_param(const std::string& name, const std::string& help, double def, double lo = 0,
                    double hi = 1) {
  return make_param(name, help, {def, def, def}, lo, hi);
}
ParamSpec num_param(const std::string& name, const std::string& help, double def, double lo, double hi) {
  return make_param(name, help, {def}, lo, hi);
}
Vec3d vec_param(const BrdfParams& p, const std::string& name) {
  const auto& v = p.values.at(name);
  return Vec3d(v[0], v[1], v[2]);
}

// The two sampling set-ups of most models here: the cosine lobe alone (diffuse-like models), or half cosine,
// half the model's own NDF (cloth, reciprocal and energy-conserving).
std::unique_ptr<BrdfModel> cosine_sampled(LambdaModel::F f, bool reciprocal, bool energy) {
  return std::make_unique<LambdaModel>(std::move(f), std::vector<Lobe>{cosine_lobe(1)}, reciprocal, energy);
}
template <class Ndf>
std::unique_ptr<BrdfModel> cosine_and_ndf_sampled(LambdaModel::F f, const Ndf& ndf) {
  return std::make_unique<LambdaModel>(std::move(f), cosine_and_ndf_lobes(ndf), true, true);
}

ModelInfo uncharted2() {
  return ModelInfo{
      "uncharted2-cloth",
      "Uncharted 2 cloth diffuse: view-dependent rim + inner + Lambert terms (empirical)",
      "RTR4 eq. 9.70 (Hable 2010)",
      {rgb_param("base-color", "diffuse albedo rho_ss", 0.8), num_param("k-rim", "rim scale", 0.3, 0, 1),
       num_param("rim-exponent", "rim falloff exponent a_rim", 2, 0, 64),
       num_param("k-inner", "inner (forward-facing) scale", 0.2, 0, 1),
       num_param("inner-exponent", "inner falloff exponent a_inner", 2, 0, 64),
       num_param("k-diff", "Lambert scale", 0.5, 0, 1)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd rho = p.rgb("base-color");
        const double kr = p.get("k-rim"), ar = p.get("rim-exponent"), ki = p.get("k-inner"),
                     ai = p.get("inner-exponent"), kd = p.get("k-diff");
        return cosine_sampled(
            [=](const Vec3d& wo, const Vec3d& wi) {
              if (!(wo.z > 0 && wi.z > 0)) return Rgbd(0);
              return uncharted2_cloth_diffuse(rho, wo.z, kr, ar, ki, ai, kd);
            },
            /*reciprocal=*/false, /*energy=*/false);
      }};
}

ModelInfo wrap() {
  return ModelInfo{
      "wrap-diffuse",
      "Uncharted 4 wrap-lighting diffuse with scatter colour (empirical; f = term / (n.l), l above n)",
      "RTR4 eq. 9.71",
      {rgb_param("base-color", "diffuse albedo rho_ss", 0.8),
       rgb_param("scatter-color", "scattering colour c_scatter", 0.0),
       num_param("wrap", "wrap width w", 0.5, 0, 1)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd rho = p.rgb("base-color"), cs = p.rgb("scatter-color");
        const double w = p.get("wrap");
        return cosine_sampled(
            [=](const Vec3d& wo, const Vec3d& wi) {
              if (!(wo.z > 0)) return Rgbd(0);
              return wrap_diffuse_brdf(rho, cs, wi.z, w);
            },
            false, false);
      }};
}

ModelInfo disney_sheen_model() {
  return ModelInfo{"disney-sheen",
                   "Disney sheen lobe k_sheen c_sheen (1 - h.l)^5 (asperity scattering; add to a diffuse)",
                   "RTR4 eq. 9.72 (Burley 2012)",
                   {rgb_param("base-color", "rho_ss, source of the sheen tint", 0.8),
                    num_param("sheen", "k_sheen", 1, 0, 1),
                    num_param("sheen-tint", "blend white -> rho/lum(rho)", 0, 0, 1)},
                   [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
                     const Rgbd c = disney_sheen_color(p.rgb("base-color"), p.get("sheen-tint"));
                     const double k = p.get("sheen");
                     // Tinting divides by luminance, so a component can exceed 1: no energy claim.
                     return cosine_sampled(
                         [=](const Vec3d& wo, const Vec3d& wi) { return disney_sheen(wo, wi, c, k); }, true,
                         false);
                   }};
}

ModelInfo velvet() {
  return ModelInfo{
      "velvet-cloth",
      "The Order: 1886 cloth: generalized velvet (inverted Gaussian) NDF, Ashikhmin-Premoze denominator",
      "RTR4 eqs. 9.73-9.74 (Ashikhmin & Premoze 2007; Neubelt & Pettineo 2013)",
      {rgb_param("base-color", "diffuse albedo rho_ss", 0.5), rgb_param("specular", "Schlick F0", 0.04),
       num_param("alpha", "width of the inverted Gaussian", 0.5, 0.01, 1),
       num_param("k-amp", "amplitude k_amp of the inverted Gaussian", 1, 0, 10)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd rho = p.rgb("base-color"), f0 = p.rgb("specular");
        const VelvetNdf<double> ndf(p.get("alpha"), p.get("k-amp"));
        return cosine_and_ndf_sampled(
            [=](const Vec3d& wo, const Vec3d& wi) { return velvet_cloth(wo, wi, rho, f0, ndf); }, ndf);
      }};
}

ModelInfo iw_sheen() {
  return ModelInfo{
      "imageworks-sheen",
      "Imageworks sheen: inverted sin^(1/a) NDF with the Estevez-Kulla fitted Smith Lambda",
      "RTR4 eq. 9.75; Estevez & Kulla 2017 (Lambda fit)",
      {rgb_param("sheen-color", "sheen colour", 1.0),
       num_param("roughness", "perceptual roughness r, alpha = r^2 (clamped >= 1e-3)", 0.5, 0, 1)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd c = p.rgb("sheen-color");
        const SheenNdf<double> ndf(roughness_to_alpha(p.get("roughness")));
        return cosine_and_ndf_sampled(
            [=](const Vec3d& wo, const Vec3d& wi) { return imageworks_sheen(wo, wi, c, ndf); }, ndf);
      }};
}

ModelInfo kk() {
  return ModelInfo{
      "kajiya-kay",
      "Kajiya-Kay micro-cylinder (fibers along the tangent x): k_d/pi + k_s/pi cos^p(beta), unnormalized",
      "Kajiya & Kay 1989; Banks 1994; RTR4 sec. 9.10.3",
      {rgb_param("diffuse", "k_d", 0.3), rgb_param("specular", "k_s", 0.2),
       num_param("exponent", "cone-lobe exponent p", 32, 0, 4096)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd kd = p.rgb("diffuse"), ks = p.rgb("specular");
        const double e = p.get("exponent");
        return cosine_sampled(
            [=](const Vec3d& wo, const Vec3d& wi) { return kajiya_kay(wo, wi, Vec3d(1, 0, 0), kd, ks, e); },
            true, false);
      }};
}

Lobe ggx_vndf_lobe(double w, const GGX<double>& g) {
  return reflect_lobe(
      w, [g](const Vec3d& wo, Vec2d u) { return g.Sample_wm(wo, u); },
      [g](const Vec3d& wo, const Vec3d& mm) { return g.PDF(wo, mm); });
}

// GGX microfacet reflection D G2 / (4 μo μi) (9.34, 9.41, 9.31) without F; finite at grazing.
double ggx_spec(const GGX<double>& g, const Vec3d& wo, const Vec3d& wi) {
  if (!(wo.z > 0 && wi.z > 0)) return 0;
  const Vec3d h = normalize(wo + wi);
  const double go = g.G1(wo), gi = g.G1(wi), den = go + gi - go * gi;
  if (!(den > 0)) return 0;
  const double v = g.D(h) * g.G1_over_cos(wo) * g.G1_over_cos(wi) / (4 * den);
  return std::isfinite(v) ? v : 0;
}

ModelInfo thin_film() {
  return ModelInfo{
      "thin-film",
      "GGX specular with thin-film interference Fresnel (film over dielectric/conductor substrate)",
      "Belcour & Barla 2017; RTR4 sec. 9.11.2",
      {num_param("roughness", "perceptual roughness r, alpha = r^2", 0.3, 0, 1),
       num_param("thickness", "film thickness d in nm", 400, 0, 2000),
       num_param("film-ior", "film IOR eta2 (relative to air)", 1.45, 1, 3),
       num_param("substrate-ior", "substrate IOR eta3", 2.9, 0.05, 10),
       num_param("substrate-k", "substrate extinction kappa3 (0 = dielectric)", 3.0, 0, 10)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const GGX<double> g(roughness_to_alpha(p.get("roughness")));
        ThinFilm<double> tf;
        tf.thickness_nm = p.get("thickness"), tf.film_ior = p.get("film-ior");
        tf.substrate_ior = p.get("substrate-ior"), tf.substrate_k = p.get("substrate-k");
        return std::make_unique<LambdaModel>(
            [=](const Vec3d& wo, const Vec3d& wi) {
              const double s = ggx_spec(g, wo, wi);
              if (!(s > 0)) return Rgbd(0);
              return tf.reflectance(dot(normalize(wo + wi), wi)) * s;
            },
            std::vector<Lobe>{ggx_vndf_lobe(1, g)}, true, true);
      }};
}

ModelInfo clearcoat() {
  return ModelInfo{
      "clearcoat",
      "Clear coat (GGX dielectric, own normal, Beer-Lambert tint) over a Lambert/GGX-metal base",
      "RTR4 sec. 9.12; Fresnel trade-off (Burley 2012), Beer-Lambert path (RTR4 sec. 14.1.2)",
      {rgb_param("base-color", "base albedo (diffuse) or F0 (metal)", 0.5),
       num_param("metallic", "base: 0 = Lambert, 1 = GGX conductor (Schlick F0 = base-color)", 0, 0, 1),
       num_param("base-roughness", "base GGX perceptual roughness", 0.5, 0, 1),
       num_param("coat-roughness", "coat GGX perceptual roughness", 0.1, 0, 1),
       num_param("coat-ior", "coat IOR (relative to air)", 1.5, 1, 3),
       rgb_param("coat-tint", "coat transmittance for one vertical traversal (1 = clear)", 1.0),
       make_param("coat-normal", "coat normal in the shading frame (normalized)", {0, 0, 1}, -1, 1)},
      [](const BrdfParams& p) -> std::unique_ptr<BrdfModel> {
        const Rgbd base = p.rgb("base-color");
        const double metal = p.get("metallic");
        const GGX<double> gb(roughness_to_alpha(p.get("base-roughness")));
        const double ac = roughness_to_alpha(p.get("coat-roughness"));
        const ClearCoat<double> coat(p.get("coat-ior"), ac, p.rgb("coat-tint"), vec_param(p, "coat-normal"));
        const GGX<double> gc(std::max(ac, GGX<double>::kMinAlpha));
        const Frame<double> cf = Frame<double>::from_z(coat.normal);
        Lobe coat_lobe = reflect_lobe(
            0.3,
            [gc, cf](const Vec3d& wo, Vec2d u) {
              const Vec3d o = cf.to_local(wo);
              return o.z > 0 ? cf.to_world(gc.Sample_wm(o, u)) : Vec3d(0, 0, 0);  // zero m: no sample
            },
            [gc, cf](const Vec3d& wo, const Vec3d& mm) {
              const Vec3d o = cf.to_local(wo), ml = cf.to_local(mm);
              return o.z > 0 ? gc.PDF(o, ml) : 0.0;
            });
        std::vector<Lobe> lobes{coat_lobe, cosine_lobe(0.7 * (1 - metal) + 1e-3)};
        if (metal > 0) lobes.push_back(ggx_vndf_lobe(0.7 * metal, gb));
        return std::make_unique<LambdaModel>(
            [=](const Vec3d& wo, const Vec3d& wi) {
              if (!(wo.z > 0 && wi.z > 0)) return Rgbd(0);
              const Vec3d h = normalize(wo + wi);
              const double w5 = std::pow(1 - saturate(dot(h, wi)), 5.0);
              const Rgbd F = base + (Rgbd(1) - base) * w5;
              const Rgbd fb = base * ((1 - metal) * kInvPi<double>)+F * (metal * ggx_spec(gb, wo, wi));
              return coat.f(wo, wi, fb);
            },
            std::move(lobes), true, true);
      }};
}

}  // namespace

std::vector<ModelInfo> extra_brdf_models() {
  return {uncharted2(), wrap(), disney_sheen_model(), velvet(), iw_sheen(), kk(), thin_film(), clearcoat()};
}

}  // namespace msh::bsdf

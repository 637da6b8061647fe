// The micro-shadowing method table (include/microshadow/occlusion/runtime/micro_shadowing_methods.h). A new
// method is one entry of kEntries: its info and a factory that binds the options and returns the evaluation.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/vcavity.h>
#include <microshadow/occlusion/micro_shadowing_anisotropic.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_early_out.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/micro_shadowing_vcavity.h>

#include <cmath>
#include <mutex>

namespace msh::occlusion {

// A validated query: α from the perceptual roughness (αy = αx unless anisotropic).
struct Point {
  double V, nl, nv, r, ax, ay;
  const double* phi;  // nullptr: the azimuth mean
};

struct MicroShadowingEvaluator::Impl {
  std::function<double(const Point&)> eval;
  // LUT methods: the tables (with and without the azimuth harmonics), loaded or baked on first use.
  std::function<std::shared_ptr<const lut::MicroShadowingLut>(bool with_phi)> table;
  // Where eval is not smooth in l (empty function: unknown, the standard circles).
  std::function<MicroShadowingBreaks(const Point&)> breaks = nullptr;
};

namespace {

using Impl = MicroShadowingEvaluator::Impl;
using Factory = std::function<Impl(const MicroShadowingOptions&, const MicroShadowingMethodInfo&)>;

struct Entry {
  MicroShadowingMethodInfo info;
  Factory make;
};

// Closed forms of (V, N·L) only.
Impl closed_form(double (*f)(double, double)) {
  return {[f](const Point& p) { return f(p.V, p.nl); }, nullptr};
}

// Number of azimuths (midpoints of equal strata of [0, π]) of the estimator's azimuth mean.
constexpr int kEstimateAzimuths = 32;

// The ALU-only approximations of the azimuth mean (occlusion/micro_shadowing_fit.h), in float as a shader
// runs them.
Impl generic_vndf_alu(const MicroShadowingOptions&, const MicroShadowingMethodInfo&) {
  return {
      [](const Point& p) {
        return double(micro_shadowing::generic_vndf_alu(float(p.V), float(p.nl), float(p.nv), float(p.r)));
      },
      nullptr};
}

// The LUT sampler an engine calls (lut/micro_shadowing_lut.h) on a table file or the default table. lut2d
// reads the N·V = 1 slice whatever the table. With φ the table must be azimuth-aware (never the mean
// silently).
Impl lut_method(const MicroShadowingOptions& o, const MicroShadowingMethodInfo& info, bool two_d) {
  struct Tables {
    std::once_flag once[2];
    std::shared_ptr<const lut::MicroShadowingLut> t[2];
  };
  auto tables = std::make_shared<Tables>();
  const std::string path = o.lut_path, name = info.name;
  if (!path.empty()) {  // a file: load now, so that a bad file fails before any evaluation
    auto t = std::make_shared<const lut::MicroShadowingLut>(lut::load_micro_shadowing_lut(path));
    const lut::MicroShadowingLutView view = t->view();
    if (!two_d && view.n_nv < 2)
      throw InputError("lut3d needs a 3D table (N.V size > 1); use --method lut2d for an N.V = 1 table");
    tables->t[0] = tables->t[1] = t;
  }
  auto table = [tables, two_d, has_file = !path.empty()](bool with_phi) {
    const int i = with_phi ? 1 : 0;
    if (!has_file)
      std::call_once(tables->once[i],
                     [&] { tables->t[i] = lut::default_micro_shadowing_lut(two_d, with_phi ? 3 : 0); });
    return tables->t[i];
  };
  return {[table, two_d](const Point& p) {
            if (micro_shadowing::exact_zero(p.V, p.nl))
              return 0.0;  // the sampler's early-out: no table needed
            const auto t = table(p.phi != nullptr);
            const lut::MicroShadowingLutView view = t->view();
            if (p.phi && view.harmonics == 0)
              throw InputError(
                  "--phi needs an azimuth-aware table (bake micro-shadowing --azimuth); this table holds the "
                  "azimuth mean only (omit --phi for the mean)");
            const double nv = two_d ? 1.0 : p.nv;
            return p.phi ? lut::sample_micro_shadowing_azimuth(view, p.V, p.nl, nv, p.r, std::cos(*p.phi))
                         : lut::sample_micro_shadowing(view, p.V, p.nl, nv, p.r);
          },
          table};
}

// The diffuse-aware term's ALU-only fit of its azimuth mean (occlusion/micro_shadowing_aware_fit.h,
// reciprocal form), in float as a shader runs it.
Impl diffuse_aware_alu() {
  return {
      [](const Point& p) {
        return double(micro_shadowing::diffuse_aware_alu(float(p.V), float(p.nl), float(p.nv), float(p.r)));
      },
      nullptr};
}

// The micro-BRDF-aware terms (docs/micro-shadowing-aware.md). specular-aware: the indicator at φ, the
// lobe-weighted azimuth mean in closed form (double) without; specular-aware-alu: that closed form in float,
// as the shaders run it. diffuse-aware(-flux): the exact quadrature (the lobe-weighted mean without φ) or,
// with samples and φ, the Sobol estimator.
// The breaks of the aware terms (reference/micro_shadowing_area_exact.h): the specular indicator's two
// curves about v and their tangent circles; the diffuse terms' early-out and cone circles.
MicroShadowingBreaks specular_aware_breaks(const Point& p) {
  MicroShadowingBreaks b;
  b.known = true;
  b.z = area::specular_aware_z_breaks(p.V, p.nv);
  if (p.phi)
    for (const area::AzimuthBreak& c : area::specular_aware_curves(p.V, lut::study_view_dir(p.nv)))
      b.curves.push_back({c.axis, c.k0, c.k1, c.k2});
  return b;
}
MicroShadowingBreaks diffuse_aware_breaks(const Point& p) {
  MicroShadowingBreaks b;
  b.known = true;
  b.z = {1 - 2 * p.V, micro_shadowing::cone_cos_from_visibility(p.V)};
  return b;
}

Impl specular_aware(bool as_float) {
  return {[as_float](const Point& p) {
            if (p.phi)
              return micro_shadowing::specular_aware(p.V, lut::study_view_dir(p.nv),
                                                     lut::study_light_dir(p.nl, *p.phi));
            if (as_float)
              return double(micro_shadowing::specular_aware_azimuth_mean<float>(float(p.V), float(p.ax),
                                                                                float(p.nl), float(p.nv)));
            return micro_shadowing::specular_aware_azimuth_mean<double>(p.V, p.ax, p.nl, p.nv);
          },
          nullptr, specular_aware_breaks};
}
Impl diffuse_aware(const MicroShadowingOptions& o, micro_shadowing::DiffuseAwareForm form) {
  return {[o, form](const Point& p) {
            const Vec3d v = lut::study_view_dir(p.nv);
            if (o.samples != 0) {
              if (!p.phi)
                throw InputError(
                    "--samples needs --phi for the diffuse-aware terms (their azimuth mean is lobe-weighted "
                    "and exact only)");
              return micro_shadowing::diffuse_aware_estimate(p.V, GGX<double>(p.ax), v,
                                                             lut::study_light_dir(p.nl, *p.phi),
                                                             int(o.samples), form, o.seed);
            }
            if (p.phi)
              return micro_shadowing::diffuse_aware_exact(p.V, p.ax, p.ax, v,
                                                          lut::study_light_dir(p.nl, *p.phi), form);
            return micro_shadowing::diffuse_aware_exact_azimuth_mean(p.V, p.ax, p.nl, p.nv, form);
          },
          nullptr, diffuse_aware_breaks};
}

// The generic term for another microsurface (docs/micro-shadowing.md, "Other microsurface profiles and
// anisotropy"): the exact quadrature at φ or its mean over [0, π], or with samples the Sobol estimator (at φ,
// or averaged over kEstimateAzimuths azimuths as generic-vndf does). exact(V, v, l) and exact_mean(p) give
// the reference; make(p) the distribution the estimator samples.
template <class Make, class Exact, class ExactMean>
Impl generic_profile(const MicroShadowingOptions& o, Make make, Exact exact, ExactMean exact_mean) {
  return {[o, make, exact, exact_mean](const Point& p) {
            const Vec3d v = lut::study_view_dir(p.nv);
            if (o.samples == 0)
              return p.phi ? exact(p, v, lut::study_light_dir(p.nl, *p.phi)) : exact_mean(p);
            const auto dist = make(p);
            const int n = int(o.samples);
            if (p.phi)
              return micro_shadowing::generic_vndf_estimate(p.V, dist, v, lut::study_light_dir(p.nl, *p.phi),
                                                            n, o.g2, o.seed);
            double sum = 0;
            for (int k = 0; k < kEstimateAzimuths; ++k) {
              const double phi = kPi<double> * (k + 0.5) / kEstimateAzimuths;
              sum += micro_shadowing::generic_vndf_estimate(p.V, dist, v, lut::study_light_dir(p.nl, phi), n,
                                                            o.g2, hash_combine(o.seed, uint32_t(k)));
            }
            return sum / kEstimateAzimuths;
          },
          nullptr};
}

// Smith–Beckmann (α = r², as GGX): the weight G2/G1 cancels, so --g2 changes only the estimator's weights.
// The generic term (Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2"): the exact
// quadrature (reference/micro_shadowing_exact.h) or, with samples, the Owen-scrambled Sobol estimator; at one
// azimuth or the mean over [0, π].
Impl generic_vndf(const MicroShadowingOptions& o, const MicroShadowingMethodInfo&) {
  return generic_profile(
      o, [](const Point& p) { return GGX<double>(p.ax, p.ay); },
      [](const Point& p, const Vec3d& v, const Vec3d& l) {
        return micro_shadowing::generic_vndf_exact(p.V, p.ax, p.ay, v, l);
      },
      [](const Point& p) {
        return p.ax == p.ay ? micro_shadowing::generic_vndf_exact_azimuth_mean(p.V, p.ax, p.nl, p.nv)
                            : micro_shadowing::generic_vndf_exact_azimuth_mean_anisotropic(p.V, p.ax, p.ay,
                                                                                           p.nl, p.nv);
      });
}

Impl generic_vndf_beckmann(const MicroShadowingOptions& o, const MicroShadowingMethodInfo&) {
  return generic_profile(
      o, [](const Point& p) { return Beckmann<double>(p.ax, p.ay); },
      [](const Point& p, const Vec3d& v, const Vec3d& l) {
        return micro_shadowing::generic_vndf_exact(p.V, Beckmann<double>(p.ax, p.ay), v, l);
      },
      [](const Point& p) {
        return micro_shadowing::generic_vndf_exact_azimuth_mean(p.V, Beckmann<double>(p.ax, p.ay), p.nl,
                                                                p.nv);
      });
}

// Beckmann–Spizzichino + V-cavity: the weight depends on m and does not cancel; --g2 selects it for the exact
// term too (height-correlated: the V-cavity's own min(G1(v,m), G1(l,m)); uncorrelated: the product).
Impl generic_vcavity(const MicroShadowingOptions& o, const MicroShadowingMethodInfo&) {
  const micro_shadowing::G2Form form = o.g2;
  const auto vc = [](const Point& p) { return BeckmannVCavity<double>(Beckmann<double>(p.ax, p.ay)); };
  return generic_profile(
      o, vc,
      [vc, form](const Point& p, const Vec3d& v, const Vec3d& l) {
        return micro_shadowing::generic_vcavity_exact(p.V, vc(p), v, l, form);
      },
      [vc, form](const Point& p) {
        return micro_shadowing::generic_vcavity_exact_azimuth_mean(p.V, vc(p), p.nl, p.nv, 0.0, form);
      });
}

// The isotropic 3D LUT at anisotropic GGX through the projected roughness
// (occlusion/micro_shadowing_anisotropic.h): v along the tangent, l at φ. At φ the azimuth-aware table
// (as lut3d); without φ the mean over kEstimateAzimuths azimuths of the plain table at each azimuth's
// projected roughness (what the term gives on average over the light's azimuth).
Impl lut3d_projected_anisotropic(const MicroShadowingOptions& o, const MicroShadowingMethodInfo& info) {
  Impl base = lut_method(o, info, false);
  auto table = base.table;
  return {
      [table](const Point& p) {
        if (micro_shadowing::exact_zero(p.V, p.nl)) return 0.0;
        const Vec3d v = lut::study_view_dir(p.nv);
        const auto rough = [&](double phi) {
          return micro_shadowing::micro_shadowing_isotropic_roughness(p.ax, p.ay, v,
                                                                      lut::study_light_dir(p.nl, phi));
        };
        if (p.phi) {
          const lut::MicroShadowingLutView view = table(true)->view();
          if (view.harmonics == 0)
            throw InputError(
                "--phi needs an azimuth-aware table (bake micro-shadowing --azimuth); this table holds the "
                "azimuth mean only (omit --phi for the mean)");
          return lut::sample_micro_shadowing_azimuth(view, p.V, p.nl, p.nv, rough(*p.phi), std::cos(*p.phi));
        }
        const lut::MicroShadowingLutView view = table(false)->view();
        double sum = 0;
        for (int k = 0; k < kEstimateAzimuths; ++k)
          sum += lut::sample_micro_shadowing(view, p.V, p.nl, p.nv,
                                             rough(kPi<double> * (k + 0.5) / kEstimateAzimuths));
        return sum / kEstimateAzimuths;
      },
      table};
}

MicroShadowingMethodInfo closed(const char* name, const char* summary) {
  return {name, summary, false, false, false, false, false, false};
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {closed("ao", "the visibility V itself (ambient occlusion applied to direct light)"),
       [](auto&, auto&) {
         return Impl{[](const Point& p) { return p.V; }, nullptr};
       }},
      {closed("reference", "step: 1 when the light is inside the visibility cone, else 0"),
       [](auto&, auto&) { return closed_form(micro_shadowing::reference_step<double>); }},
      {closed("brinck-maximov-2016", "Brinck & Maximov 2016, 'The Technical Art of Uncharted 4'"),
       [](auto&, auto&) { return closed_form(micro_shadowing::brinck_maximov_2016<double>); }},
      {closed("chan-2018", "Chan 2018, 'Material Advances in Call of Duty: WWII'"),
       [](auto&, auto&) { return closed_form(micro_shadowing::chan_2018<double>); }},
      {closed("part1-analytic", "Zurita 2026, 'Improving Direct Lighting Material Occlusion - Part 1'"),
       [](auto&, auto&) { return closed_form(micro_shadowing::part1_analytic<double>); }},
      {{"generic-vndf",
        "generic VNDF-based term (Zurita 2026, Part 2): exact quadrature, or the Sobol estimator with "
        "samples",
        true, true, true, true, true, false},
       generic_vndf},
      {{"generic-vndf-alu", "ALU-only fit of the generic term's azimuth mean (micro_shadowing_fit.h), float",
        true, true, false, false, false, false},
       generic_vndf_alu},
      {{"lut3d", "the LUT sampler on a 3D table (V, N.L, N.V x roughness)", true, true, true, false, false,
        true},
       [](auto& o, auto& i) { return lut_method(o, i, false); }},
      {{"lut2d", "the LUT sampler on the N.V = 1 slice", true, false, true, false, false, true},
       [](auto& o, auto& i) { return lut_method(o, i, true); }},
      {{"specular-aware",
        "micro-BRDF-aware, specular lobe: chi(n.h > c) chi(h.l > c); without --phi its GGX-lobe-weighted "
        "azimuth mean (closed form)",
        true, true, true, false, false, false},
       [](auto&, auto&) { return specular_aware(false); }},
      {{"specular-aware-alu", "the specular-aware azimuth mean's closed form in float, as the shaders run it",
        true, true, false, false, false, false},
       [](auto&, auto&) { return specular_aware(true); }},
      {{"diffuse-aware",
        "micro-BRDF-aware, Lambertian facets, reciprocal cone tests (exact quadrature; Sobol estimator with "
        "--samples and --phi)",
        true, true, true, false, true, false},
       [](auto& o, auto&) { return diffuse_aware(o, micro_shadowing::DiffuseAwareForm::Reciprocal); }},
      {{"diffuse-aware-flux",
        "micro-BRDF-aware, Lambertian facets, fraction of the reflected flux leaving through the cone", true,
        true, true, false, true, false},
       [](auto& o, auto&) { return diffuse_aware(o, micro_shadowing::DiffuseAwareForm::Flux); }},
      {{"diffuse-aware-alu",
        "ALU-only fit of the diffuse-aware (reciprocal) term's azimuth mean (micro_shadowing_aware_fit.h), "
        "float",
        true, true, false, false, false, false},
       [](auto&, auto&) { return diffuse_aware_alu(); }},
      {{"generic-vndf-beckmann",
        "generic term for Smith-Beckmann (exact quadrature, or the Sobol estimator with samples)", true, true,
        true, true, true, false},
       generic_vndf_beckmann},
      {{"generic-vcavity",
        "generic term for Beckmann-Spizzichino + V-cavity, weight G2/G1 depends on m (exact quadrature, or "
        "the weighted Sobol estimator with samples)",
        true, true, true, true, true, false},
       generic_vcavity},
      {{"lut3d-projected-anisotropic",
        "the 3D LUT at anisotropic GGX through the rms of the roughness projected along l and v", true, true,
        true, true, false, true},
       lut3d_projected_anisotropic},
  };
  return e;
}

void require_unit(double x, const char* what) {
  if (!(x >= 0 && x <= 1)) throw InputError(fmt::format("{} must be in [0, 1], got {}", what, x));
}

}  // namespace

const std::vector<MicroShadowingMethodInfo>& micro_shadowing_methods() {
  static const std::vector<MicroShadowingMethodInfo> infos = [] {
    std::vector<MicroShadowingMethodInfo> v;
    for (const Entry& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

const MicroShadowingMethodInfo* find_micro_shadowing_method(const std::string& name) {
  for (const MicroShadowingMethodInfo& i : micro_shadowing_methods())
    if (i.name == name) return &i;
  return nullptr;
}

std::string micro_shadowing_method_names() {
  std::string s;
  for (const MicroShadowingMethodInfo& i : micro_shadowing_methods()) s += (s.empty() ? "" : ", ") + i.name;
  return s;
}

MicroShadowingEvaluator::MicroShadowingEvaluator(const std::string& method, MicroShadowingOptions options)
    : info_(find_micro_shadowing_method(method)), options_(std::move(options)) {
  if (!info_)
    throw InputError(
        fmt::format("--method must be one of: {}; got '{}'", micro_shadowing_method_names(), method));
  if (options_.samples != 0 && !info_->accepts_samples)
    throw InputError(fmt::format("--samples does not apply to {}", method));
  if (options_.samples < 0 || options_.samples > (int64_t(1) << 30))
    throw InputError(fmt::format("--samples must be in [1, 2^30], got {}", options_.samples));
  if (!options_.lut_path.empty() && !info_->accepts_lut)
    throw InputError(fmt::format("--lut does not apply to {}", method));
  const size_t i = size_t(info_ - micro_shadowing_methods().data());
  impl_ = std::make_shared<const Impl>(entries()[i].make(options_, *info_));
}

namespace {
Point validated_point(const MicroShadowingMethodInfo* info_, const MicroShadowingQuery& q) {
  require_unit(q.visibility, "--visibility");
  require_unit(q.n_dot_l, "--ndotl");
  require_unit(q.n_dot_v, "--ndotv");
  require_unit(q.roughness, "--roughness");
  if (q.phi) {
    if (!info_->accepts_phi)
      throw InputError(
          fmt::format("--phi does not apply to {} (it does not depend on the azimuth)", info_->name));
    if (!(*q.phi >= 0 && *q.phi <= kPi<double>))
      throw InputError(fmt::format("--phi (relative azimuth, radians) must be in [0, pi], got {}", *q.phi));
  }
  if (q.roughness_y) {
    if (!info_->accepts_roughness_y)
      throw InputError(fmt::format("--roughness-y does not apply to {} (isotropic)", info_->name));
    require_unit(*q.roughness_y, "--roughness-y");
  }
  const double ax = roughness_to_alpha(q.roughness);
  const double ay = q.roughness_y ? roughness_to_alpha(*q.roughness_y) : ax;
  return Point{q.visibility, q.n_dot_l, q.n_dot_v, q.roughness, ax, ay, q.phi ? &*q.phi : nullptr};
}
}  // namespace

double MicroShadowingEvaluator::eval(const MicroShadowingQuery& q) const {
  return impl_->eval(validated_point(info_, q));
}

MicroShadowingBreaks MicroShadowingEvaluator::breaks(const MicroShadowingQuery& q) const {
  if (!impl_->breaks) return {};
  return impl_->breaks(validated_point(info_, q));
}

std::shared_ptr<const lut::MicroShadowingLut> MicroShadowingEvaluator::table(bool with_phi) const {
  return impl_->table ? impl_->table(with_phi) : nullptr;
}

}  // namespace msh::occlusion

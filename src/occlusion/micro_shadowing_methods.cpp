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
#include <microshadow/occlusion/directional.h>
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
#include <microshadow/shader/portable.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <nlohmann/json.hpp>
#include <stdexcept>

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
  // The renderer's per-light value (MicroShadowingEvaluator::shade).
  std::function<float(const MicroShadowingShadeInput&)> shade = nullptr;
};

namespace {

using Impl = MicroShadowingEvaluator::Impl;
using Factory = std::function<Impl(const MicroShadowingOptions&, const MicroShadowingMethodInfo&)>;

struct Entry {
  MicroShadowingMethodInfo info;
  Factory make;
};

// Closed forms of (V, N·L) only: the double form for eval, the float form (as a shader runs it) for shade.
Impl closed_form(double (*f)(double, double), float (*g)(float, float)) {  // f<double>, f<float>
  Impl i{[f](const Point& p) { return f(p.V, p.nl); }, nullptr};
  i.shade = [g](const MicroShadowingShadeInput& in) { return g(in.visibility, in.l.z); };
  return i;
}

// The GGX of a shading point: α from the perceptual roughness, floored at r = 0.02 (a mirror has no VNDF to
// sample).
float shade_alpha(const MicroShadowingShadeInput& in) {
  return roughness_to_alpha(std::max(in.roughness, 0.02f));
}

// Number of azimuths (midpoints of equal strata of [0, π]) of the estimator's azimuth mean.
constexpr int kEstimateAzimuths = 32;

// The ALU-only approximations of the azimuth mean (occlusion/micro_shadowing_fit.h), in float as a shader
// runs them.
Impl generic_vndf_alu(const MicroShadowingOptions&, const MicroShadowingMethodInfo&) {
  Impl i{[](const Point& p) {
           return double(micro_shadowing::generic_vndf_alu(float(p.V), float(p.nl), float(p.nv), float(p.r)));
         },
         nullptr};
  i.shade = [](const MicroShadowingShadeInput& in) {
    return micro_shadowing::generic_vndf_alu(in.visibility, in.l.z, in.v.z, in.roughness);
  };
  return i;
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
  Impl i{[table, two_d](const Point& p) {
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
  // Per light: an azimuth-aware file is sampled at the light's azimuth (never reduced to its mean silently),
  // any other table at (V, N·L, N·V); the default table is the plain one.
  i.shade = [table, two_d](const MicroShadowingShadeInput& in) {
    if (micro_shadowing::exact_zero(in.visibility, in.l.z)) return 0.0f;  // Zurita 2026 early-out: no fetch
    const lut::MicroShadowingLutView view = table(false)->view();
    const float nv = two_d ? 1.0f : in.v.z;
    if (view.harmonics > 0) {
      const float d = std::sqrt((in.v.x * in.v.x + in.v.y * in.v.y) * (in.l.x * in.l.x + in.l.y * in.l.y));
      const float cos_phi = d > 0.0f ? clamp((in.v.x * in.l.x + in.v.y * in.l.y) / d, -1.0f, 1.0f) : 1.0f;
      return lut::sample_micro_shadowing_azimuth(view, in.visibility, in.l.z, nv, in.roughness, cos_phi);
    }
    return lut::sample_micro_shadowing(view, in.visibility, in.l.z, nv, in.roughness);
  };
  return i;
}

// The diffuse-aware term's ALU-only fit of its azimuth mean (occlusion/micro_shadowing_aware_fit.h,
// reciprocal form), in float as a shader runs it.
Impl diffuse_aware_alu() {
  Impl i{
      [](const Point& p) {
        return double(micro_shadowing::diffuse_aware_alu(float(p.V), float(p.nl), float(p.nv), float(p.r)));
      },
      nullptr};
  i.shade = [](const MicroShadowingShadeInput& in) {
    return micro_shadowing::diffuse_aware_alu(in.visibility, in.l.z, in.v.z, in.roughness);
  };
  return i;
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
  Impl i{[as_float](const Point& p) {
           if (p.phi)
             return micro_shadowing::specular_aware(p.V, lut::study_view_dir(p.nv),
                                                    lut::study_light_dir(p.nl, *p.phi));
           if (as_float)
             return double(micro_shadowing::specular_aware_azimuth_mean<float>(float(p.V), float(p.ax),
                                                                               float(p.nl), float(p.nv)));
           return micro_shadowing::specular_aware_azimuth_mean<double>(p.V, p.ax, p.nl, p.nv);
         },
         nullptr, specular_aware_breaks};
  // Per light: the indicator at the full vectors; the ALU form is the azimuth mean's closed form (N·L, N·V).
  if (as_float)
    i.shade = [](const MicroShadowingShadeInput& in) {
      return micro_shadowing::specular_aware_azimuth_mean<float>(in.visibility, shade_alpha(in), in.l.z,
                                                                 in.v.z);
    };
  else
    i.shade = [](const MicroShadowingShadeInput& in) {
      return micro_shadowing::specular_aware(in.visibility, in.v, in.l);
    };
  return i;
}
Impl diffuse_aware(const MicroShadowingOptions& o, micro_shadowing::DiffuseAwareForm form) {
  Impl i{[o, form](const Point& p) {
           const Vec3d v = lut::study_view_dir(p.nv);
           if (o.samples != 0) {
             if (!p.phi)
               throw InputError(
                   "--samples needs --phi for the diffuse-aware terms (their azimuth mean is lobe-weighted "
                   "and exact only)");
             return micro_shadowing::diffuse_aware_estimate(
                 p.V, GGX<double>(p.ax), v, lut::study_light_dir(p.nl, *p.phi), int(o.samples), form, o.seed);
           }
           if (p.phi)
             return micro_shadowing::diffuse_aware_exact(p.V, p.ax, p.ax, v,
                                                         lut::study_light_dir(p.nl, *p.phi), form);
           return micro_shadowing::diffuse_aware_exact_azimuth_mean(p.V, p.ax, p.nl, p.nv, form);
         },
         nullptr, diffuse_aware_breaks};
  // Per light: the Sobol estimator (float, as the shaders run it) or, without samples, the exact quadrature.
  i.shade = [o, form](const MicroShadowingShadeInput& in) {
    if (micro_shadowing::exact_zero(in.visibility, in.l.z)) return 0.0f;
    const float a = shade_alpha(in);
    if (o.samples == 0)
      return float(micro_shadowing::diffuse_aware_exact(double(in.visibility), double(a), double(a),
                                                        Vec3d(in.v), Vec3d(in.l), form));
    return micro_shadowing::diffuse_aware_estimate(in.visibility, GGX<float>(a), in.v, in.l, int(o.samples),
                                                   form, (o.seed ^ in.seed) | 1u);
  };
  return i;
}

// The generic term for another microsurface (docs/micro-shadowing.md, "Other microsurface profiles and
// anisotropy"): the exact quadrature at φ or its mean over [0, π], or with samples the Sobol estimator (at φ,
// or averaged over kEstimateAzimuths azimuths as generic-vndf does). exact(V, v, l) and exact_mean(p) give
// the reference; make(p) the distribution the estimator samples.
// Per light (shade): the estimator on make_f(α) in float with the options' samples, else the exact term.
template <class Make, class MakeF, class Exact, class ExactMean>
Impl generic_profile(const MicroShadowingOptions& o, Make make, MakeF make_f, Exact exact,
                     ExactMean exact_mean) {
  Impl i{[o, make, exact, exact_mean](const Point& p) {
           const Vec3d v = lut::study_view_dir(p.nv);
           if (o.samples == 0) return p.phi ? exact(p, v, lut::study_light_dir(p.nl, *p.phi)) : exact_mean(p);
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
  i.shade = [o, make_f, exact](const MicroShadowingShadeInput& in) {
    if (micro_shadowing::exact_zero(in.visibility, in.l.z)) return 0.0f;
    const float a = shade_alpha(in);
    if (o.samples == 0) {
      const Point p{in.visibility, in.l.z, in.v.z, in.roughness, a, a, nullptr};
      return float(exact(p, Vec3d(in.v), Vec3d(in.l)));
    }
    return micro_shadowing::generic_vndf_estimate(in.visibility, make_f(a), in.v, in.l, int(o.samples), o.g2,
                                                  (o.seed ^ in.seed) | 1u);
  };
  return i;
}

// Smith–Beckmann (α = r², as GGX): the weight G2/G1 cancels, so --g2 changes only the estimator's weights.
// The generic term (Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2"): the exact
// quadrature (reference/micro_shadowing_exact.h) or, with samples, the Owen-scrambled Sobol estimator; at one
// azimuth or the mean over [0, π].
Impl generic_vndf(const MicroShadowingOptions& o, const MicroShadowingMethodInfo&) {
  return generic_profile(
      o, [](const Point& p) { return GGX<double>(p.ax, p.ay); }, [](float a) { return GGX<float>(a); },
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
      [](float a) { return Beckmann<float>(a); },
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
      o, vc, [](float a) { return BeckmannVCavity<float>(Beckmann<float>(a)); },
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
  Impl i{
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
  i.shade = base.shade;  // a renderer's roughness is isotropic: the plain LUT
  return i;
}

// What an entry reads and accepts (MicroShadowingMethodInfo's flags).
enum Flag : unsigned {
  kRough = 1,     // uses the roughness
  kNdotV = 2,     // uses N·V
  kPhi = 4,       // accepts --phi
  kRoughY = 8,    // accepts --roughness-y
  kSamples = 16,  // accepts --samples
  kLut = 32,      // accepts --lut
  kNoNdotl = 64,  // does not depend on N·L
  kStudy = 128,   // in the study's default list
  kTexel =
      256,  // reads the per-texel directional channels (the renderer, the study and the viewer; eval throws)
  kNoVis = 512,  // does not read V (the micro-occlusion map)
};
MicroShadowingMethodInfo info(const char* name, const char* label, const char* summary, unsigned f,
                              std::vector<MicroShadowingGlsl> glsl = {}) {
  MicroShadowingMethodInfo i;
  i.name = name, i.label = label, i.summary = summary;
  i.uses_roughness = f & kRough, i.uses_ndotv = f & kNdotV;
  i.accepts_phi = f & kPhi, i.accepts_roughness_y = f & kRoughY;
  i.accepts_samples = f & kSamples, i.accepts_lut = f & kLut;
  i.uses_ndotl = !(f & kNoNdotl), i.in_study = f & kStudy;
  i.needs_texel = f & kTexel;
  if (i.needs_texel) i.texel_channels = directional::kDirectionalChannels, i.texel_bake = "gen-material";
  i.uses_visibility = !(f & kNoVis);
  i.glsl = std::move(glsl);
  return i;
}
// The 21 channels of the view correction (directional::kViewChannels) instead of the 9.
MicroShadowingMethodInfo view_channels(MicroShadowingMethodInfo i) {
  i.texel_channels = directional::kViewChannels, i.texel_bake = "gen-material --directional-view";
  return i;
}
// A term of per-texel channels: the renderer's per-light value; eval throws (there is no texel).
Impl texel_term(const MicroShadowingMethodInfo& info,
                std::function<float(const MicroShadowingShadeInput&)> shade) {
  const std::string msg =
      fmt::format("{} reads per-texel channels: render or study a material baked with them ({})", info.name,
                  info.texel_bake);
  Impl i{[msg](const Point&) -> double { throw InputError(msg); }, nullptr};
  i.shade = std::move(shade);
  return i;
}
// When to use it (MicroShadowingMethodInfo::use; docs/choosing.md).
MicroShadowingMethodInfo used(const char* use, MicroShadowingMethodInfo i) {
  i.use = use;
  return i;
}
// A named pair: the diffuse-lobe term d and the specular-lobe term s (both single-term entries).
MicroShadowingMethodInfo pair(const char* d, const char* s, const char* label, const char* summary,
                              unsigned f, const char* use = "") {
  MicroShadowingMethodInfo i = used(use, info("", label, summary, f));
  i.uses_visibility = false;  // as its terms (entries())
  i.name = std::string(d) + "+" + s;
  i.diffuse = d, i.specular = s;
  return i;
}
MicroShadowingGlsl glsl(const char* expr, const char* requires_fn = "", const char* lut = "") {
  MicroShadowingGlsl g;
  g.expr = expr, g.requires_fn = requires_fn, g.lut = lut;
  return g;
}
// A GLSL form that reads the per-texel directional channels (MicroShadowingGlsl::texel).
MicroShadowingGlsl texel_glsl(const char* expr, const char* requires_fn) {
  MicroShadowingGlsl g = glsl(expr, requires_fn);
  g.texel = true;
  return g;
}
// The GLSL form of a closed form of (V, N·L) named fn in shaders/glsl: fn(vis, nl), and, where
// shaders/portable/micro_shadowing_area.h has it (cap), its spherical-cap form fn_area_cap(vis, nl_cap, rho)
// (MicroShadowingGlsl::area_cap; without it the three.js module's area lights take the term at the light's
// axis).
MicroShadowingGlsl vnl_glsl(const std::string& fn, bool cap = true) {
  MicroShadowingGlsl g;
  g.expr = fn + "(vis, nl)", g.requires_fn = fn;
  if (cap) g.area_cap = fn + "_area_cap(vis, nl_cap, rho)";
  return g;
}
// The double path of a closed form written only once, in shaders/portable (msh::shader, float32): closed<
// in_float<msh::shader::fn>, msh::shader::fn>(...) evaluates the shader's own function, in float.
template <float (*G)(float, float)>
double in_float(double v, double n_dot_l) {
  return double(G(float(v), float(n_dot_l)));
}
template <double (*F)(double, double), float (*G)(float, float)>
Impl closed_entry(const MicroShadowingOptions&, const MicroShadowingMethodInfo&) {
  return closed_form(F, G);
}
// A closed form of (V, N·L) alone: its info names it (MicroShadowingMethodInfo::closed_form).
template <double (*F)(double, double), float (*G)(float, float)>
Entry closed(MicroShadowingMethodInfo i) {
  i.closed_form = F;
  return {std::move(i), closed_entry<F, G>};
}
// The registry's table sampled (3: at N·V; 2: at N·V = 1, the 2D slice).
MicroShadowingMethodInfo table_sampler(MicroShadowingMethodInfo i, int dims) {
  i.table_sample = dims;
  return i;
}
template <class T>
T visibility_term(T v, T) {
  return v;
}
Impl constant_entry(double c) {
  Impl i{[c](const Point&) { return c; }, nullptr};
  i.shade = [c](const MicroShadowingShadeInput&) { return float(c); };
  return i;
}

const std::vector<Entry>& entries() {
  namespace ms = micro_shadowing;
  using In = MicroShadowingShadeInput;
  static const std::vector<Entry> e = [] {
    std::vector<Entry> v = {
        {used("the baseline: no micro-occlusion",
              info("none", "none (term = 1)", "no micro-occlusion: the term is 1", kNoNdotl | kNoVis | kStudy,
                   {glsl("1.0")})),
         [](auto&, auto&) { return constant_entry(1.0); }},
        closed<visibility_term<double>, visibility_term<float>>(
            used("not for direct light: AO was never a light-direction term",
                 info("ao", "AO on direct light (term = V)",
                      "the visibility V itself (ambient occlusion applied to direct light)",
                      kNoNdotl | kStudy, {glsl("vis")}))),
        closed<ms::reference_step<double>, ms::reference_step<float>>(
            used("reference of the cone model only",
                 info("reference", "reference step (Zurita 2026)",
                      "step: 1 when the light is inside the visibility cone, else 0", kStudy,
                      {vnl_glsl("msh_ms_reference_step")}))),
        closed<ms::brinck_maximov_2016<double>, ms::brinck_maximov_2016<float>>(
            used("legacy (Uncharted 4)", info("brinck-maximov-2016", "Brinck & Maximov 2016",
                                              "Brinck & Maximov 2016, 'The Technical Art of Uncharted 4'",
                                              kStudy, {vnl_glsl("msh_ms_brinck_maximov2016")}))),
        closed<ms::chan_2018<double>, ms::chan_2018<float>>(used(
            "legacy (CoD WWII, Filament)",
            info("chan-2018", "Chan 2018 (Filament)", "Chan 2018, 'Material Advances in Call of Duty: WWII'",
                 kStudy, {vnl_glsl("msh_ms_chan2018")}))),
        closed<in_float<shader::msh_ms_hdrp_micro_shadows>, shader::msh_ms_hdrp_micro_shadows>(
            used("legacy, faded (Unity HDRP): Brinck & Maximov 2016 at 85% opacity",
                 info("hdrp-micro-shadows", "Unity HDRP Micro Shadows (opacity 0.85)",
                      "Unity HDRP's ComputeMicroShadowing: lerp(1, Brinck & Maximov 2016, 0.85)", 0,
                      {vnl_glsl("msh_ms_hdrp_micro_shadows", false)}))),
        closed<ms::part1_analytic<double>, ms::part1_analytic<float>>(
            used("legacy (Zurita 2026 Part 1)",
                 info("part1-analytic", "Part 1 analytic (Zurita 2026)",
                      "Zurita 2026, 'Improving Direct Lighting Material Occlusion - Part 1'", kStudy,
                      {vnl_glsl("msh_ms_part1_analytic")}))),
        {used("reference views and offline; N samples per light",
              info("generic-vndf", "generic VNDF (Zurita 2026)",
                   "generic VNDF-based term (Zurita 2026, Part 2): exact quadrature, or the Sobol estimator "
                   "with samples",
                   kRough | kNdotV | kPhi | kRoughY | kSamples | kStudy, {[] {
                     MicroShadowingGlsl g =
                         glsl("msh_ms_generic_vndf_estimate(vis, vec2(alpha), v, l, u_samples, true, 1u)",
                              "msh_ms_generic_vndf_estimate");
                     g.label_suffix = ", N samples", g.samples = g.frame = true;
                     return g;
                   }()})),
         generic_vndf},
        {used("specular lobe with only a V map, no table",
              info("generic-vndf-alu", "generic VNDF, ALU fit",
                   "ALU-only fit of the generic term's azimuth mean (micro_shadowing_fit.h), float",
                   kRough | kNdotV | kStudy,
                   {[] {
                      MicroShadowingGlsl g =
                          glsl("msh_ms_generic_vndf_alu(vis, nl, nv, rough)", "msh_ms_generic_vndf_alu");
                      g.area_cap = "msh_ms_generic_vndf_alu_area_cap(vis, nl_cap, nv, rough, rho)";
                      return g;
                    }(),
                    [] {
                      MicroShadowingGlsl g = glsl(
                          "msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(vis, nv, rough), nl)",
                          "msh_ms_generic_vndf_alu_light");
                      g.id_suffix = "-two-stage", g.label_suffix = " (pixel + light)", g.two_stage = true;
                      return g;
                    }()})),
         generic_vndf_alu},
        {table_sampler(used("specular lobe with only a V map, table allowed",
                            info("lut3d", "3D LUT (cone layout)",
                                 "the LUT sampler on a 3D table (V, N.L, N.V x roughness)",
                                 kRough | kNdotV | kPhi | kLut | kStudy,
                                 {glsl("msh_ms_lut_sample_cone(u_lut3d, u_lut3d_slabs, vis, nl, nv, rough)",
                                       "msh_ms_lut_sample_cone", "lut3d"),
                                  [] {
                                    MicroShadowingGlsl g = glsl(
                                        "msh_ms_lut_sample_cone_azimuth(u_lut_az, u_lut_az_slabs, "
                                        "u_lut_az_harmonics, vis, nl, nv, rough, cos_phi)",
                                        "msh_ms_lut_sample_cone_azimuth", "lut_azimuth");
                                    g.id_suffix = "-azimuth",
                                    g.label_suffix = ", azimuth-aware (3 harmonics)", g.phi = true;
                                    return g;
                                  }()})),
                       3),
         [](auto& o, auto& i) { return lut_method(o, i, false); }},
        {table_sampler(used("as lut3d where N·V is not available",
                            info("lut2d", "2D LUT (N·V = 1 slice)", "the LUT sampler on the N.V = 1 slice",
                                 kRough | kPhi | kLut | kStudy,
                                 {glsl("msh_ms_lut_sample_cone(u_lut2d, u_lut2d_slabs, vis, nl, 1.0, rough)",
                                       "msh_ms_lut_sample_cone", "lut2d")})),
                       2),
         [](auto& o, auto& i) { return lut_method(o, i, true); }},
        {info("specular-aware", "specular-aware (indicator)",
              "micro-BRDF-aware, specular lobe: chi(n.h > c) chi(h.l > c); without --phi its "
              "GGX-lobe-weighted azimuth mean (closed form)",
              kRough | kNdotV | kPhi, {[] {
                MicroShadowingGlsl g = glsl("msh_ms_specular_aware(vis, v, l)", "msh_ms_specular_aware");
                g.phi = true;  // the indicator at the pixel's own azimuth
                return g;
              }()}),
         [](auto&, auto&) { return specular_aware(false); }},
        {info("specular-aware-alu", "specular-aware, closed-form mean",
              "the specular-aware azimuth mean's closed form in float, as the shaders run it",
              kRough | kNdotV,
              {glsl("msh_ms_specular_aware_azimuth_mean(vis, alpha, nl, nv)",
                    "msh_ms_specular_aware_azimuth_mean")}),
         [](auto&, auto&) { return specular_aware(true); }},
        {info("diffuse-aware", "diffuse-aware",
              "micro-BRDF-aware, Lambertian facets, reciprocal cone tests (exact quadrature; Sobol estimator "
              "with --samples and --phi)",
              kRough | kNdotV | kPhi | kSamples),
         [](auto& o, auto&) { return diffuse_aware(o, micro_shadowing::DiffuseAwareForm::Reciprocal); }},
        {info("diffuse-aware-flux", "diffuse-aware (flux form)",
              "micro-BRDF-aware, Lambertian facets, fraction of the reflected flux leaving through the cone",
              kRough | kNdotV | kPhi | kSamples),
         [](auto& o, auto&) { return diffuse_aware(o, micro_shadowing::DiffuseAwareForm::Flux); }},
        {info("diffuse-aware-alu", "diffuse-aware, ALU fit",
              "ALU-only fit of the diffuse-aware (reciprocal) term's azimuth mean "
              "(micro_shadowing_aware_fit.h), float",
              kRough | kNdotV,
              {glsl("msh_ms_diffuse_aware_alu(vis, nl, nv, rough)", "msh_ms_diffuse_aware_alu")}),
         [](auto&, auto&) { return diffuse_aware_alu(); }},
        {info("generic-vndf-beckmann", "generic VNDF, Smith-Beckmann",
              "generic term for Smith-Beckmann (exact quadrature, or the Sobol estimator with samples)",
              kRough | kNdotV | kPhi | kRoughY | kSamples),
         generic_vndf_beckmann},
        {info("generic-vcavity", "generic, V-cavity",
              "generic term for Beckmann-Spizzichino + V-cavity, weight G2/G1 depends on m (exact "
              "quadrature, or the weighted Sobol estimator with samples)",
              kRough | kNdotV | kPhi | kRoughY | kSamples),
         generic_vcavity},
        {info("lut3d-projected-anisotropic", "3D LUT, projected anisotropic roughness",
              "the 3D LUT at anisotropic GGX through the rms of the roughness projected along l and v",
              kRough | kNdotV | kPhi | kRoughY | kLut),
         lut3d_projected_anisotropic},
        // Directional micro-occlusion (occlusion/directional.h, docs/directional-occlusion.md): the
        // footprint's mean diffuse transport lit · (n_fine · l)⁺ from 9 linear channels, as a factor on (n ·
        // l)⁺.
        {used("relief with 9 channels only (4.5 B as BC5 + BC4): directional-view is closer at every scale "
              "for 12 more channels",
              info("directional", "directional (9 linear channels)",
                   "directional micro-occlusion: the mean lit * N.L over the texel's footprint from 9 linear "
                   "channels baked from the height map, divided by the shading N.L (renderer, study and "
                   "viewer)",
                   kNoNdotl | kNoVis | kStudy | kTexel,
                   {texel_glsl("msh_dir_term(dir_c0, dir_c1, dir_c8, l_t, n_t)", "msh_dir_term")})),
         [](auto&, auto& info) {
           return texel_term(info, [](const In& in) {
             if (in.texel_channels < directional::kDirectionalChannels) return 1.0f;
             return directional::directional_term(in.texel, in.l_tangent, in.n_tangent);
           });
         }},
        // The same with the view correction (directional_view_term): 21 channels, the 9 and the 12 slope
        // channels G_x, G_y that weight each facet by its projected area toward the camera.
        {view_channels(used(
             "relief (a height map exists): ship this, on both lobes (on all materials together the closest "
             "term on the diffuse, the specular and the total at every scale of the 1024² and 2048² studies; "
             "per material not everywhere: docs/study.md); 21 B at 8 bits is over the 12 B budget, 10.5 B as "
             "BC5 + BC4 with --directional-bc (11 fetches per pixel)",
             info("directional-view", "directional, view-corrected (21 linear channels)",
                  "directional micro-occlusion with the view correction: the 9 channels plus 12 slope "
                  "channels that weight each facet by its projected area toward the camera (renderer, study "
                  "and viewer)",
                  kNoNdotl | kNoVis | kStudy | kTexel,
                  {texel_glsl("msh_dir_view_term(dir_v, l_t, view_t, n_t)", "msh_dir_view_term")}))),
         [](auto&, auto& info) {
           return texel_term(info, [](const In& in) {
             if (in.texel_channels < directional::kViewChannels) return 1.0f;
             return directional::directional_view_term(in.texel, in.l_tangent, in.v_tangent, in.n_tangent);
           });
         }},
        // The same 21 channels with masking toward the camera (directional_view_masked_term): the material's
        // slope covariance Σ spreads the projected areas as Smith's masking does. Renderer and study only.
        {view_channels(
             info("directional-view-masked", "directional, view-corrected and masked (21 channels + Σ)",
                  "directional-view with masking toward the camera: the projected areas spread by the "
                  "material's slope covariance (Smith-normalised; renderer and study)",
                  kNoNdotl | kNoVis | kTexel)),
         [](auto&, auto& info) {
           return texel_term(info, [](const In& in) {
             if (in.texel_channels < directional::kViewChannels) return 1.0f;
             static constexpr float kZero[3] = {0, 0, 0};
             return directional::directional_view_masked_term(
                 in.texel, in.l_tangent, in.v_tangent, in.n_tangent,
                 in.slope_covariance ? in.slope_covariance : kZero);
           });
         }},
        // Named pairs (docs/micro-shadowing-aware.md): the diffuse-aware term on the diffuse lobe, a specular
        // term on the specular lobe.
        {pair("diffuse-aware", "specular-aware", "aware (estimator + indicator)",
              "micro-BRDF-aware pair: the diffuse-aware estimator, the specular-aware indicator", kStudy,
              "reference of the aware pair; N samples per light"),
         nullptr},
        {pair("diffuse-aware-flux", "specular-aware", "aware, flux form",
              "the pair with the diffuse-aware flux form", kStudy, "research variant"),
         nullptr},
        {pair("diffuse-aware-alu", "specular-aware", "aware ALU + specular indicator",
              "the diffuse-aware ALU fit, the specular-aware indicator", kStudy, "research variant"),
         nullptr},
        {pair("diffuse-aware-alu", "generic-vndf-alu", "recommended, ALU only",
              "the recommended pair in ALU only: the diffuse-aware fit on the diffuse lobe, the generic "
              "term's fit on the specular lobe",
              kStudy, "only a V (AO) map, no table: ship this"),
         nullptr},
        {pair("diffuse-aware-alu", "lut3d", "recommended, ALU + LUT",
              "the recommended pair with the table: the diffuse-aware fit on the diffuse lobe, the 3D LUT on "
              "the specular lobe",
              kStudy, "only a V (AO) map, table allowed: ship this"),
         nullptr},
        {pair("directional", "generic-vndf-alu", "directional + generic ALU (specular)",
              "directional micro-occlusion on the diffuse lobe, the generic term's ALU fit on the specular "
              "lobe",
              kStudy,
              "research variant: the generic fit on the specular lobe is farther off than directional there"),
         nullptr},
        {pair("directional-view", "generic-vndf-alu", "directional view-corrected + generic ALU (specular)",
              "view-corrected directional micro-occlusion on the diffuse lobe, the generic term's ALU fit on "
              "the specular lobe",
              kStudy,
              "research variant: the generic fit on the specular lobe is farther off than directional-view "
              "there"),
         nullptr},
        {pair("diffuse-aware", "generic-vndf", "recommended, estimators",
              "the recommended pair's reference: the diffuse-aware and generic estimators", 0),
         nullptr},
    };
    // A pair reads and accepts what its terms do.
    for (Entry& p : v) {
      if (!p.info.is_pair()) continue;
      for (const std::string& part : {p.info.diffuse, p.info.specular}) {
        const auto it = std::find_if(v.begin(), v.end(), [&](const Entry& x) { return x.info.name == part; });
        if (it == v.end() || it->info.is_pair()) throw std::logic_error("micro-shadowing pair part: " + part);
        const MicroShadowingMethodInfo& t = it->info;
        p.info.uses_roughness |= t.uses_roughness, p.info.uses_ndotv |= t.uses_ndotv;
        p.info.accepts_phi |= t.accepts_phi, p.info.accepts_roughness_y |= t.accepts_roughness_y;
        p.info.accepts_samples |= t.accepts_samples, p.info.accepts_lut |= t.accepts_lut;
        p.info.needs_texel |= t.needs_texel, p.info.uses_visibility |= t.uses_visibility;
        p.info.texel_channels = std::max(p.info.texel_channels, t.texel_channels);
        if (!t.texel_bake.empty()) p.info.texel_bake = t.texel_bake;
      }
    }
    return v;
  }();
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

std::string micro_shadowing_method_json(const MicroShadowingMethodInfo& i) {
  nlohmann::json glsl = nlohmann::json::array();
  for (const MicroShadowingGlsl& g : i.glsl)
    glsl.push_back({{"id", i.form_id(g)}, {"expr", g.expr}, {"requires", g.requires_fn}, {"lut", g.lut}});
  const nlohmann::json j = {{"name", i.name},
                            {"label", i.label},
                            {"summary", i.summary},
                            {"diffuse", i.is_pair() ? i.diffuse : i.name},
                            {"specular", i.is_pair() ? i.specular : i.name},
                            {"pair", i.is_pair()},
                            {"in_study", i.in_study},
                            {"uses_ndotl", i.uses_ndotl},
                            {"uses_roughness", i.uses_roughness},
                            {"uses_ndotv", i.uses_ndotv},
                            {"accepts_phi", i.accepts_phi},
                            {"accepts_roughness_y", i.accepts_roughness_y},
                            {"accepts_samples", i.accepts_samples},
                            {"accepts_lut", i.accepts_lut},
                            {"needs_texel", i.needs_texel},
                            {"texel_channels", i.texel_channels},
                            {"texel_bake", i.texel_bake},
                            {"uses_visibility", i.uses_visibility},
                            {"table_sample", i.table_sample},
                            {"use", i.use},
                            {"glsl", glsl}};
  return j.dump();
}

std::vector<std::string> micro_shadowing_closed_form_terms() {
  std::vector<std::string> v;
  for (const MicroShadowingMethodInfo& m : micro_shadowing_methods())
    if (m.closed_form && m.uses_ndotl) v.push_back(m.name);
  return v;
}

std::vector<std::string> micro_shadowing_study_methods() {
  std::vector<std::string> r;
  for (const MicroShadowingMethodInfo& i : micro_shadowing_methods())
    if (i.in_study) r.push_back(i.name);
  return r;
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
  if (info_->is_pair()) {
    // Each term gets the options that apply to it.
    const auto part = [&](const std::string& name) {
      const MicroShadowingMethodInfo& t = *find_micro_shadowing_method(name);
      MicroShadowingOptions o = options_;
      if (!t.accepts_samples) o.samples = 0;
      if (!t.accepts_lut) o.lut_path.clear();
      return std::make_shared<const MicroShadowingEvaluator>(name, o);
    };
    diffuse_ = part(info_->diffuse), specular_ = part(info_->specular);
    return;
  }
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
  if (info_->is_pair())
    throw InputError(
        fmt::format("{} is a pair ({} on the diffuse lobe, {} on the specular lobe): it has one "
                    "value per lobe",
                    info_->name, info_->diffuse, info_->specular));
  return impl_->eval(validated_point(info_, q));
}

std::pair<double, double> MicroShadowingEvaluator::eval_lobes(const MicroShadowingQuery& q) const {
  if (!info_->is_pair()) {
    const double t = eval(q);
    return {t, t};
  }
  validated_point(info_, q);
  // A term that does not read φ or the anisotropy gets the query without them (its value is the same).
  const auto part = [&](const MicroShadowingEvaluator& e) {
    MicroShadowingQuery p = q;
    if (!e.info().accepts_phi) p.phi.reset();
    if (!e.info().accepts_roughness_y) p.roughness_y.reset();
    return e.eval(p);
  };
  return {part(*diffuse_), part(*specular_)};
}

MicroShadowingLobes MicroShadowingEvaluator::shade(const MicroShadowingShadeInput& in) const {
  if (info_->is_pair()) return {diffuse_->shade(in).diffuse, specular_->shade(in).specular};
  const float t = impl_->shade(in);
  return {t, t};
}

MicroShadowingBreaks MicroShadowingEvaluator::breaks(const MicroShadowingQuery& q) const {
  if (info_->is_pair() || !impl_->breaks) return {};
  return impl_->breaks(validated_point(info_, q));
}

std::shared_ptr<const lut::MicroShadowingLut> MicroShadowingEvaluator::table(bool with_phi) const {
  if (info_->is_pair()) {
    if (auto t = specular_->table(with_phi)) return t;
    return diffuse_->table(with_phi);
  }
  return impl_->table ? impl_->table(with_phi) : nullptr;
}

}  // namespace msh::occlusion

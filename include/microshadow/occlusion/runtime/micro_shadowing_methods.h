// The micro-shadowing methods by name: the one list of terms. `eval micro-shadowing`, the renderer
// (`render --method`, scene files), the multiscale study and its report, the demo, the Python module and the
// viewer's method menu all dispatch through it, so a new term is added in one place
// (src/occlusion/micro_shadowing_methods.cpp: one entry = its info and a factory). A method is one term on
// both lobes of the BRDF, or a named pair: one term on the diffuse lobe and another on the specular lobe.
//
// Runtime code (std::function, a table, table loading through lut/micro_shadowing_loader.h): not part of the
// header-only core. Each method's math lives in the core headers the entry names (occlusion/, lut/,
// reference/); docs/micro-shadowing.md describes the terms.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace msh::lut {
struct MicroShadowingLut;
}

namespace msh::occlusion {

// One evaluation point, in the convention of docs/micro-shadowing.md: v = (sin θv, 0, N·V), l at relative
// azimuth φ ∈ [0, π] about the normal. Without phi a method that depends on the azimuth gives its mean over
// φ ∈ [0, π] (what a LUT texel stores). roughness is perceptual (α = r²); roughness_y makes GGX anisotropic
// (roughness along the tangent x, roughness_y along y) for the methods that accept it.
struct MicroShadowingQuery {
  double visibility = 1, n_dot_l = 1, n_dot_v = 1, roughness = 0.5;
  std::optional<double> phi;
  std::optional<double> roughness_y;
};

// Options fixed for an evaluator: samples > 0 asks for the Sobol estimator where a method has one (else the
// exact value); seed scrambles it; g2 is the Smith form of the estimator's weight; lut_path a table file for
// the LUT methods (empty: the default table, baked on first use).
struct MicroShadowingOptions {
  int64_t samples = 0;
  uint32_t seed = 1;
  micro_shadowing::G2Form g2 = micro_shadowing::G2Form::HeightCorrelated;
  std::string lut_path;
};

// The viewer's GLSL form of a method (the viewer's server generates its methods.js from these,
// src/view/viewer_server.cpp): expr is a GLSL ES 3.00 float expression over the names listed in
// docs/viewer.md (vis, nl, nv, rough, alpha, cos_phi, v, l, u_samples, the LUT samplers); requires_fn names
// the GLSL function it calls (the method is left out of the menu when the shader files lack it); lut the
// table it samples. id_suffix and label_suffix tell apart several forms of one method (e.g. the two-stage ALU
// fit); phi/samples/frame/two_stage tell the browser test how to evaluate the C++ side (at the pixel's
// azimuth, with the page's sample count, at the pixel's own v and l, per pixel + per light). texel: the form
// reads the per-texel directional channels, which the page fetches once per pixel into dir_c0, dir_c1 (vec4)
// and dir_c8 (float), and all 21 of the view correction into dir_v[6] (vec4, channels 4k..4k+3), with the
// light l_t, the view view_t and the shading normal n_t in the normal map's tangent frame (the viewer offers
// it only for a texture set baked with as many channels as the method reads; the browser test evaluates the
// C++ term at the probed channels).
struct MicroShadowingGlsl {
  std::string expr, requires_fn, lut, id_suffix, label_suffix;
  bool phi = false, samples = false, frame = false, two_stage = false, texel = false;
  // The term's form for a spherical-cap light (shaders/glsl/micro_shadowing_area.glsl; docs/area-lights.md):
  // a float expression over vis, nl_cap (N·L of the cap's axis), rho (its angular radius), nv, rough; empty:
  // none (an engine uses the point term at the cap's axis). The three.js module's rect-area lights use it.
  std::string area_cap;
};

// What a method reads and accepts (the CLI, the Python module and the viewer use it to reject options that do
// not apply, never to ignore them silently), and where it is used.
struct MicroShadowingMethodInfo {
  std::string name, summary;
  bool uses_roughness = false, uses_ndotv = false;
  bool accepts_phi = false, accepts_roughness_y = false, accepts_samples = false, accepts_lut = false;
  // Short name for menus and legends.
  std::string label;
  // A pair: the method names of the diffuse-lobe and specular-lobe terms (both empty: one term on both).
  std::string diffuse, specular;
  // Depends on N·L (false for `none` and `ao`: the renderer's smooth-normal ablation skips them).
  bool uses_ndotl = true;
  // Rendered by the multiscale study by default (a term the renderer runs per shading point at a cost the
  // study affords: closed forms, ALU fits, tables, estimators; not exact quadrature).
  bool in_study = false;
  // Reads per-texel data beyond V (MicroShadowingShadeInput::texel): the renderer (shade) and the viewer
  // (its GLSL form, flagged texel) evaluate it, eval throws; texel_channels is how many channels it reads.
  bool needs_texel = false;
  int texel_channels = 0;
  // The command that bakes those channels (e.g. gen-material --directional-view).
  std::string texel_bake;
  // Reads V, the micro-occlusion map (false for none and the directional terms, which read texel channels).
  bool uses_visibility = true;
  // When to use it, one phrase (docs/choosing.md's "use" column; set for the study's methods).
  std::string use;
  // The viewer's forms (none: not in the viewer).
  std::vector<MicroShadowingGlsl> glsl;
  // What a caller may run in its own loop instead of MicroShadowingEvaluator::eval, with the same values (the
  // Python module's fast path): closed_form, the term as a function of (V, N·L) alone; table_sample, the
  // registry's own table sampled at (V, N·L, N·V, roughness) (3) or at N·V = 1 (2; 0: not a table sampler).
  double (*closed_form)(double visibility, double n_dot_l) = nullptr;
  int table_sample = 0;
  bool is_pair() const { return !diffuse.empty(); }
  // The id of one of its GLSL forms, as the viewer, `methods --json` and the measuring commands name it: the
  // method's name + the form's id_suffix (e.g. generic-vndf-alu-two-stage).
  std::string form_id(const MicroShadowingGlsl& g) const { return name + g.id_suffix; }
};

// One shading point as a renderer sees it, in the term's frame (n = +z): V from the micro-occlusion map,
// perceptual roughness, unit v and l (towards the eye and the light; v.z > 0), and the random stream of a
// Monte Carlo term. No validation: the caller clamps.
struct MicroShadowingShadeInput {
  float visibility = 1, roughness = 0.5f;
  Vec3f v{0, 0, 1}, l{0, 0, 1};
  uint32_t seed = 1;
  // Methods with needs_texel: the per-texel channels (occlusion/directional.h), with l, v (towards the eye)
  // and the shading normal in the texture's tangent space (x = +u, y = +v as the normal map, z = the
  // unperturbed surface normal).
  const float* texel = nullptr;
  int texel_channels = 0;
  Vec3f l_tangent{0, 0, 1}, n_tangent{0, 0, 1}, v_tangent{0, 0, 1};
  // The material's slope covariance (Σ_xx, Σ_xy, Σ_yy; `directional-view-masked`).
  const float* slope_covariance = nullptr;
};
// The term of each lobe (equal for a single term).
struct MicroShadowingLobes {
  float diffuse = 1, specular = 1;
};

// Every method, in a fixed order.
const std::vector<MicroShadowingMethodInfo>& micro_shadowing_methods();
// The names of the methods with in_study, in table order.
std::vector<std::string> micro_shadowing_study_methods();
// The names of the closed forms of (V, N·L) that depend on N·L (closed_form and uses_ndotl), in table order:
// the older terms that verify micro-shadowing-term and plot micro-shadowing-fit compare.
std::vector<std::string> micro_shadowing_closed_form_terms();
// nullptr when there is no method of that name.
const MicroShadowingMethodInfo* find_micro_shadowing_method(const std::string& name);
// "a, b, c" of every method name (for error messages and --help).
std::string micro_shadowing_method_names();
// Every field of method m as the text of one JSON object: `microshadow methods --json` prints a list of them
// and Python's micro_shadowing_methods(details=True) returns them as dicts (glsl: a list of {id, expr,
// requires, lut}; diffuse and specular: the method's own name unless it is a pair).
std::string micro_shadowing_method_json(const MicroShadowingMethodInfo& m);

// Where a method's value, as a function of the light direction l (n·l = l.z, φ = the azimuth of l; v in
// the xz plane at azimuth 0, as in MicroShadowingQuery), jumps or kinks: circles of constant n·l (z) and
// curves {l : l·axis = k0 + k1 n·l + k2 (n·l)²}. The area-light quadrature makes them panel edges
// (reference/runtime/micro_shadowing_area_method.h). known = false: the method lists none, and the circles of
// every built-in term of occlusion/micro_shadowing.h are used.
struct MicroShadowingBreaks {
  struct Curve {
    Vec3d axis{0, 0, 1};
    double k0 = 0, k1 = 0, k2 = 0;
  };
  bool known = false;
  std::vector<double> z;
  std::vector<Curve> curves;
};

// A method bound to its options. eval() is const and thread-safe. Errors (an unknown method, an option the
// method does not accept, an input outside [0, 1] or φ outside [0, π], an unreadable table) throw
// msh::InputError with the message the CLI prints.
class MicroShadowingEvaluator {
 public:
  explicit MicroShadowingEvaluator(const std::string& method, MicroShadowingOptions options = {});
  // One term's value (a pair: InputError; use eval_lobes).
  double eval(const MicroShadowingQuery& q) const;
  // Both lobes' values (equal for a single term).
  std::pair<double, double> eval_lobes(const MicroShadowingQuery& q) const;
  // The renderer's evaluation per light, in float: at the full vectors (an azimuth-dependent term at its
  // azimuth; a method with samples through its Sobol estimator with options().samples samples, else its exact
  // or closed form). Never throws; finite for any unit v, l.
  MicroShadowingLobes shade(const MicroShadowingShadeInput& in) const;
  // The breaks of eval() in l at the query's V, N·V, roughness (and whether φ is set); n_dot_l is ignored.
  MicroShadowingBreaks breaks(const MicroShadowingQuery& q) const;
  const MicroShadowingMethodInfo& info() const { return *info_; }
  const MicroShadowingOptions& options() const { return options_; }
  // LUT methods: the table eval() reads for a query with or without φ (baked or loaded on first use; the
  // default table is not baked for an early-out query). nullptr for the other methods.
  std::shared_ptr<const lut::MicroShadowingLut> table(bool with_phi) const;

  // The bound evaluation of one method (validated inputs; α already from roughness). Public for the table.
  struct Impl;

 private:
  const MicroShadowingMethodInfo* info_;
  MicroShadowingOptions options_;
  std::shared_ptr<const Impl> impl_;
  // A pair's two terms.
  std::shared_ptr<const MicroShadowingEvaluator> diffuse_, specular_;
};

}  // namespace msh::occlusion

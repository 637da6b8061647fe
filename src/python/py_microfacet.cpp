// microshadow.ndf_D / ndf_lambda / ndf_G1 / ndf_G2 / vndf_pdf / sample_vndf: the NDFs of
// include/microshadow/microfacet/ (GGX, Beckmann, Blinn-Phong, GTR) vectorized over directions and roughness.
// Parameters follow `microshadow eval microfacet`: --ndf ggx|beckmann|blinn-phong|gtr, alpha (Blinn-Phong:
// the Beckmann-equivalent α, exponent 2α⁻² − 2), alpha_y (GGX, Beckmann), gamma (GTR).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>
#include <microshadow/microfacet/masking.h>

#include <memory>
#include <optional>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;

enum class Ndf { Ggx, Beckmann, BlinnPhong, Gtr };

Ndf parse_ndf(const std::string& s) {
  if (s == "ggx") return Ndf::Ggx;
  if (s == "beckmann") return Ndf::Beckmann;
  if (s == "blinn-phong") return Ndf::BlinnPhong;
  if (s == "gtr") return Ndf::Gtr;
  throw InputError(fmt::format("--ndf must be one of ggx, beckmann, blinn-phong, gtr; got '{}'", s));
}

// The NDF of one element. GTR builds a Λ table in its constructor, so its α and γ are one value per call.
struct NdfArgs {
  Ndf ndf;
  bool has_alpha_y;
  std::shared_ptr<const GTR<double>> gtr;
};

NdfArgs prepare_ndf(const std::string& name, pyb::handle alpha, pyb::handle alpha_y, double gamma) {
  NdfArgs a{parse_ndf(name), !alpha_y.is_none(), nullptr};
  require_range(gamma, 0.05, 20.0, "--gamma");  // every NDF: a NaN gamma is refused even where unused
  if ((a.ndf == Ndf::BlinnPhong || a.ndf == Ndf::Gtr) && a.has_alpha_y)
    throw InputError(a.ndf == Ndf::Gtr ? "--alpha-y: GTR is isotropic"
                                       : "--alpha-y: Blinn-Phong is isotropic");
  if (a.ndf == Ndf::Gtr) {
    if (!(PyFloat_Check(alpha.ptr()) || PyLong_Check(alpha.ptr())))
      throw pyb::value_error("gtr: alpha must be one number per call (its Λ table is built once)");
    const double al = alpha.cast<double>();
    require_range(al, 0.0, 4.0, "--alpha");
    a.gtr = std::make_shared<const GTR<double>>(al, gamma);
  }
  return a;
}

// Calls f(dist) with the distribution of element i (ax, ay already read and range-checked).
template <class F>
double with_ndf(const NdfArgs& a, double ax, double ay, F&& f) {
  switch (a.ndf) {
    case Ndf::Ggx:
      return f(GGX<double>(ax, ay));
    case Ndf::Beckmann:
      return f(Beckmann<double>(ax, ay));
    case Ndf::BlinnPhong:
      return f(BlinnPhong<double>(blinn_phong_exponent_from_beckmann(std::max(ax, 1e-4))));
    default:
      return f(*a.gtr);
  }
}

// Reads α (and α_y) of element i with the CLI's checks.
template <class R>
std::pair<double, double> alphas(const NdfArgs& a, const R& r, std::size_t i, std::size_t ia,
                                 std::size_t iay) {
  const double ax = r(ia, i);
  require_range(ax, 0.0, 4.0, "--alpha");
  double ay = ax;
  if (a.has_alpha_y) {
    ay = r(iay, i);
    require_range(ay, 0.0, 4.0, "--alpha-y");
  }
  return {ax, ay};
}

// One-direction quantities (D of m, Λ / G1 of w): f(dist, vec).
template <class F>
pyb::object one_dir(const std::string& ndf, pyb::handle w, const char* wname, pyb::handle alpha,
                    pyb::handle alpha_y, double gamma, F&& f) {
  const NdfArgs a = prepare_ndf(ndf, alpha, alpha_y, gamma);
  std::vector<ArgSpec> args = {{w, wname, 3, Domain::Direction}, {alpha, "alpha", 0, Domain::Checked}};
  if (a.has_alpha_y) args.push_back({alpha_y, "alpha_y", 0, Domain::Checked});
  const Broadcast b = broadcast(args);
  return map_scalar(b, [&](const auto& r, std::size_t i) {
    const auto [ax, ay] = alphas(a, r, i, 1, 2);
    const Vec3d v = r.vec(0, i);
    return with_ndf(a, ax, ay, [&](const auto& d) { return f(d, v); });
  });
}

// Quantities of a direction w and a microfacet normal m (G1(w, m), D_w(m)): f(dist, w, m).
template <class F>
pyb::object two_dir(const std::string& ndf, pyb::handle w, pyb::handle wm, pyb::handle alpha,
                    pyb::handle alpha_y, double gamma, F&& f) {
  const NdfArgs a = prepare_ndf(ndf, alpha, alpha_y, gamma);
  std::vector<ArgSpec> args = {
      {w, "w", 3, Domain::Direction}, {wm, "m", 3, Domain::Direction}, {alpha, "alpha", 0, Domain::Checked}};
  if (a.has_alpha_y) args.push_back({alpha_y, "alpha_y", 0, Domain::Checked});
  const Broadcast b = broadcast(args);
  return map_scalar(b, [&](const auto& r, std::size_t i) {
    const auto [ax, ay] = alphas(a, r, i, 2, 3);
    const Vec3d v = r.vec(0, i), h = r.vec(1, i);
    return with_ndf(a, ax, ay, [&](const auto& d) { return f(d, v, h); });
  });
}

// Binds name(ndf, <dir>, alpha=0.5, alpha_y=None, gamma=2) -> one_dir(..., f).
template <class F>
void def_one_dir(pyb::module_& m, const char* name, const char* dir, F f, const std::string& doc) {
  m.def(
      name,
      [dir, f](const std::string& ndf, pyb::handle w, pyb::handle alpha, pyb::handle alpha_y, double gamma) {
        return one_dir(ndf, w, dir, alpha, alpha_y, gamma, f);
      },
      "ndf"_a, pyb::arg(dir), "alpha"_a = 0.5, "alpha_y"_a = pyb::none(), "gamma"_a = 2.0, doc.c_str());
}

enum class G2Kind { HeightCorrelated, Separable, DirectionCorrelated, HeightDirectionCorrelated };

G2Kind parse_g2(const std::string& s) {
  if (s == "height-correlated") return G2Kind::HeightCorrelated;
  if (s == "separable" || s == "uncorrelated") return G2Kind::Separable;
  if (s == "direction-correlated") return G2Kind::DirectionCorrelated;
  if (s == "height-direction-correlated") return G2Kind::HeightDirectionCorrelated;
  throw InputError(fmt::format(
      "form must be one of height-correlated, separable, direction-correlated, height-direction-correlated; "
      "got '{}'",
      s));
}

// ndf_G2: without m the height-correlated G2(wo, wi); with m the chosen form at that microfacet normal.
auto ndf_G2(const std::string& ndf, pyb::handle wo, pyb::handle wi, pyb::handle wm, const std::string& form,
            const std::string& lambda_phi, pyb::handle alpha, pyb::handle alpha_y, double gamma) {
  const G2Kind kind = parse_g2(form);
  const bool van = lambda_phi == "van-ginneken";
  if (!van && lambda_phi != "ashikhmin")
    throw InputError(fmt::format("lambda_phi must be ashikhmin or van-ginneken; got '{}'", lambda_phi));
  if (wm.is_none() && kind != G2Kind::HeightCorrelated)
    throw pyb::value_error(fmt::format("form '{}' needs the microfacet normal m", form));
  const NdfArgs a = prepare_ndf(ndf, alpha, alpha_y, gamma);
  std::vector<ArgSpec> args = {{wo, "wo", 3, Domain::Direction},
                               {wi, "wi", 3, Domain::Direction},
                               {alpha, "alpha", 0, Domain::Checked}};
  if (a.has_alpha_y) args.push_back({alpha_y, "alpha_y", 0, Domain::Checked});
  const std::size_t im = args.size();
  if (!wm.is_none()) args.push_back({wm, "m", 3, Domain::Direction});
  const Broadcast b = broadcast(args);
  return map_scalar(b, [&](const auto& r, std::size_t i) {
    const auto [ax, ay] = alphas(a, r, i, 2, 3);
    const Vec3d o = r.vec(0, i), l = r.vec(1, i);
    return with_ndf(a, ax, ay, [&](const auto& d) -> double {
      if (wm.is_none()) return d.G2(o, l);
      const Vec3d h = r.vec(im, i);
      const auto lam = [van](double p) { return van ? lambda_van_ginneken(p) : lambda_ashikhmin(p); };
      switch (kind) {
        case G2Kind::HeightCorrelated:
          return G2_height_correlated(d, o, l, h);
        case G2Kind::Separable:
          return G2_separable(d, o, l, h);
        case G2Kind::DirectionCorrelated:
          return G2_direction_correlated(d, o, l, h, lam);
        default:
          return G2_height_direction_correlated(d, o, l, h, lam);
      }
    });
  });
}

// sample_vndf: GGX (spherical caps or Heitz 2018) or Beckmann visible normals from uniform numbers.
auto sample_vndf(const std::string& ndf, pyb::handle w, pyb::handle u, pyb::handle alpha, pyb::handle alpha_y,
                 const std::string& sampler) {
  const NdfArgs a = prepare_ndf(ndf, alpha, alpha_y, 2.0);
  if (a.ndf != Ndf::Ggx && a.ndf != Ndf::Beckmann)
    throw InputError(fmt::format("sample_vndf: ndf must be ggx or beckmann; got '{}'", ndf));
  const bool heitz = sampler == "heitz-2018";
  if (!heitz && sampler != "spherical-caps")
    throw InputError(fmt::format("sampler must be spherical-caps or heitz-2018; got '{}'", sampler));
  if (heitz && a.ndf != Ndf::Ggx) throw InputError("sampler heitz-2018 is GGX only");
  // u: (..., 2) uniform numbers in [0, 1)
  std::vector<ArgSpec> args = {
      {w, "w", 3, Domain::Direction}, {u, "u", 2, Domain::Uniform}, {alpha, "alpha", 0, Domain::Checked}};
  if (a.has_alpha_y) args.push_back({alpha_y, "alpha_y", 0, Domain::Checked});
  const Broadcast b = broadcast(args);
  return map_vec3(b, [&](const auto& r, std::size_t i) -> Vec3d {
    const auto [ax, ay] = alphas(a, r, i, 2, 3);
    const Vec3d v = r.vec(0, i);
    const Vec2d uv(r(1, i, 0), r(1, i, 1));
    if (a.ndf == Ndf::Beckmann) return Beckmann<double>(ax, ay).Sample_wm(v, uv);
    const GGX<double> g(ax, ay);
    return heitz ? g.sample_vndf_heitz2018(v, uv) : g.sample_vndf_spherical_caps(v, uv);
  });
}

}  // namespace

void register_microfacet(pyb::module_& m) {
  const char* common =
      "\n\nndf: 'ggx', 'beckmann', 'blinn-phong' or 'gtr'. alpha: roughness alpha in [0, 4] (an array, "
      "broadcast; for blinn-phong the Beckmann-equivalent alpha, exponent 2/alpha^2 - 2; for gtr one number "
      "per call). alpha_y: alpha along y (ggx, beckmann; None = isotropic). gamma: GTR tail exponent in "
      "[0.05, 20] (2 = GGX). Directions are arrays of shape (..., 3) in the local frame (n = +z), broadcast "
      "against each other and against alpha like numpy ufuncs; float32 in -> float32 out.";

  def_one_dir(
      m, "ndf_D", "m", [](const auto& d, const Vec3d& v) { return double(d.D(v)); },
      std::string("NDF D(m) (RTR4 eq. 9.52 Beckmann, 9.53 GGX; GTR: Burley 2012), normalized so that "
                  "the integral of D(m)(n.m) over the sphere is 1; 0 for m.z <= 0.") +
          common);
  def_one_dir(
      m, "ndf_lambda", "w", [](const auto& d, const Vec3d& v) { return double(d.Lambda(v)); },
      std::string("Smith Lambda(w) of the NDF (RTR4 eq. 9.37 for GGX; exact Beckmann form; GTR from its "
                  "numerical table).") +
          common);
  m.def(
      "ndf_G1",
      [](const std::string& ndf, pyb::handle w, pyb::handle wm, pyb::handle alpha, pyb::handle alpha_y,
         double gamma) {
        if (wm.is_none())
          return one_dir(ndf, w, "w", alpha, alpha_y, gamma,
                         [](const auto& d, const Vec3d& v) { return double(d.G1(v)); });
        return two_dir(ndf, w, wm, alpha, alpha_y, gamma,
                       [](const auto& d, const Vec3d& v, const Vec3d& h) { return double(d.G1(v, h)); });
      },
      "ndf"_a, "w"_a, "m"_a = pyb::none(), "alpha"_a = 0.5, "alpha_y"_a = pyb::none(), "gamma"_a = 2.0,
      (std::string("Smith masking G1(w) = 1/(1 + Lambda(w)) (RTR4 eq. 9.24); with m, times the chi+ factor "
                   "(0 when w sees the back of the microfacet).") +
       common)
          .c_str());
  m.def(
      "ndf_G2", &ndf_G2, "ndf"_a, "wo"_a, "wi"_a, "m"_a = pyb::none(), "form"_a = "height-correlated",
      "lambda_phi"_a = "ashikhmin", "alpha"_a = 0.5, "alpha_y"_a = pyb::none(), "gamma"_a = 2.0,
      (std::string("Smith masking-shadowing G2(wo, wi[, m]). form: 'height-correlated' (RTR4 eq. 9.31; "
                   "without m: no chi+ factors), 'separable' (9.27), 'direction-correlated' (9.28), "
                   "'height-direction-correlated' (9.32); the last three need m. lambda_phi: 'ashikhmin' or "
                   "'van-ginneken' (the lambda(phi) of 9.28 / 9.32).") +
       common)
          .c_str());
  m.def(
      "vndf_pdf",
      [](const std::string& ndf, pyb::handle w, pyb::handle wm, pyb::handle alpha, pyb::handle alpha_y,
         double gamma) {
        return two_dir(ndf, w, wm, alpha, alpha_y, gamma,
                       [](const auto& d, const Vec3d& v, const Vec3d& h) { return double(d.D(v, h)); });
      },
      "ndf"_a, "w"_a, "m"_a, "alpha"_a = 0.5, "alpha_y"_a = pyb::none(), "gamma"_a = 2.0,
      (std::string("Distribution of visible normals D_w(m) = G1(w)(w.m)+ D(m)/|w.z| (Heitz 2014), the "
                   "solid-angle pdf of sample_vndf.") +
       common)
          .c_str());
  m.def("sample_vndf", &sample_vndf, "ndf"_a, "w"_a, "u"_a, "alpha"_a = 0.5, "alpha_y"_a = pyb::none(),
        "sampler"_a = "spherical-caps",
        "Samples visible normals m ~ D_w(m) for view direction w (shape (..., 3)) from uniform numbers u "
        "(shape (..., 2), in [0, 1)); returns unit normals, shape (..., 3). ndf: 'ggx' (sampler "
        "'spherical-caps', Dupuy & Benyoub 2023, or 'heitz-2018', Heitz 2018) or 'beckmann'. alpha, alpha_y "
        "as for ndf_D (broadcast).");
}

}  // namespace msh::py

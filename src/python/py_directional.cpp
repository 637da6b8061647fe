// microshadow.directional_transport / directional_term / directional_view_transport / directional_view_term /
// bake_directional_channels: the directional micro-occlusion run time of include/microshadow/occlusion/
// directional.h (9 linear channels per texel, 21 with the view correction; tangent space of the normal map),
// vectorized, and the bake of render/directional_bake.h.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>

#include <array>
#include <cmath>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;
namespace dir = msh::directional;

constexpr int kCh = dir::kDirectionalChannels, kViewCh = dir::kViewChannels;

// A unit-direction argument, shape (..., 3).
struct Dir {
  pyb::handle obj;
  const char* name;
};

// f(c, d) per element of `channels` (shape (..., n)) broadcast with the directions: c holds the element's n
// channels as double (the library's functions are templated on the scalar), d[k] its k-th direction. The
// output dtype is the broadcast one (float32 in, float32 out).
template <class F, class... D>
pyb::object map_channels(pyb::handle channels, int n, F f, D... dirs) {
  const Broadcast b = broadcast({{channels, "channels", n}, {dirs.obj, dirs.name, 3, Domain::Direction}...});
  return map_scalar(b, [&](const auto& r, std::size_t i) {
    double c[kViewCh];
    for (int k = 0; k < n; ++k) c[k] = r(0, i, k);
    std::array<Vec3d, sizeof...(D)> d;
    for (std::size_t k = 0; k < d.size(); ++k) d[k] = r.vec(k + 1, i);
    return f(c, d);
  });
}

// A 2-D height array (values in [0, 1], each side in [8, 16384], as `bake directional` reads a file).
render::Texture height_texture(pyb::handle obj) {
  const auto a = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2)
    throw pyb::value_error("height must be a 2-D array of shape (height, width), values in [0, 1]");
  const pyb::ssize_t h = a.shape(0), w = a.shape(1);
  if (h < 8 || w < 8 || h > 16384 || w > 16384)
    throw InputError(fmt::format("height: each side must be in [8, 16384], got {}x{}", w, h));
  render::Texture t(int(w), int(h), 1);
  const float* p = a.data();
  for (pyb::ssize_t j = 0; j < h; ++j)
    for (pyb::ssize_t i = 0; i < w; ++i) {
      const float v = p[j * w + i];
      if (!(v >= 0.0f && v <= 1.0f))
        throw InputError(fmt::format("height: {} at texel ({}, {}) is outside [0, 1]", v, i, j));
      t.at(int(i), int(j), 0) = v;
    }
  return t;
}

}  // namespace

void register_directional(pyb::module_& m) {
  m.def(
      "directional_transport",
      [](pyb::handle channels, pyb::handle l) {
        auto f = [](const double* c, const auto& d) { return dir::directional_transport(c, d[0]); };
        return map_channels(channels, kCh, f, Dir{l, "light"});
      },
      "channels"_a, "light"_a,
      "Directional micro-occlusion (occlusion/directional.h): the mean diffuse transport lit * max(n_fine . "
      "l, 0) over a texel's footprint, max(0, sum_i c_i b_i(l)) with b(l) = (1, x, y, z, xz, yz, x^2 - y^2, "
      "xy, z^2), 0 for l.z <= 0. channels: shape (..., 9) (bake_directional_channels, or any box mean of "
      "it: a mip level); light: shape (..., 3), unit, in the normal map's tangent space (x = +u columns, y "
      "= +v rows top to bottom, z = the flat surface normal); not normalized here. Broadcast like ufuncs; "
      "float32 in -> float32 out. Diffuse radiance = albedo/pi * E * transport.");
  m.def(
      "directional_term",
      [](pyb::handle channels, pyb::handle l, pyb::handle n) {
        auto f = [](const double* c, const auto& d) { return dir::directional_term(c, d[0], d[1]); };
        return map_channels(channels, kCh, f, Dir{l, "light"}, Dir{n, "normal"});
      },
      "channels"_a, "light"_a, "normal"_a,
      "directional_transport as a factor on the engine's max(n . l, 0): transport / (n . l), 0 where n . l "
      "<= 1e-4 (n: the coarse shading normal in the same tangent space, unit). Not clamped to 1: near the "
      "coarse terminator lit facets can exceed the coarse cosine. Shapes as directional_transport plus "
      "normal (..., 3).");
  m.def(
      "directional_view_transport",
      [](pyb::handle channels, pyb::handle l, pyb::handle v) {
        auto f = [](const double* c, const auto& d) {
          return dir::directional_view_transport(c, c + kCh, d[0], d[1]);
        };
        return map_channels(channels, kViewCh, f, Dir{l, "light"}, Dir{v, "view"});
      },
      "channels"_a, "light"_a, "view"_a,
      "The view-corrected transport (occlusion/directional.h directional_view_transport): the footprint's "
      "mean of lit * max(n_fine . l, 0) as a camera along `view` averages it, weighting each facet by its "
      "projected area: max(0, T(l) + (G_x(l) v_x + G_y(l) v_y) / max(v_z, 0.5)). channels: shape (..., 21) "
      "(bake_directional_channels(view=True): T's 9, then G_x's and G_y's 6 on (1, x, y, z, xz, yz), or any "
      "box mean of it); light and view: shape (..., 3), unit, tangent space as directional_transport, view "
      "toward the camera. 0 for l.z <= 0.");
  m.def(
      "directional_view_term",
      [](pyb::handle channels, pyb::handle l, pyb::handle v, pyb::handle n) {
        auto f = [](const double* c, const auto& d) {
          return dir::directional_view_term(c, d[0], d[1], d[2]);
        };
        return map_channels(channels, kViewCh, f, Dir{l, "light"}, Dir{v, "view"}, Dir{n, "normal"});
      },
      "channels"_a, "light"_a, "view"_a, "normal"_a,
      "directional_view_transport as a factor on the engine's max(n . l, 0) (the renderer's "
      "`directional-view` method): 0 where n . l <= 1e-4; not clamped to 1.");
  m.def(
      "bake_directional_channels",
      [](pyb::handle height, double depth_texels, int azimuths, double max_distance, bool view) {
        if (!(depth_texels > 0 && depth_texels <= 1e4))
          throw InputError(fmt::format("depth must be in (0, 10000] texels, got {}", depth_texels));
        if (!std::isfinite(max_distance))
          throw InputError(
              fmt::format("max_distance must be finite (<= 0: unlimited), got {}", max_distance));
        const render::Texture h = height_texture(height);
        render::Texture ch;
        {
          pyb::gil_scoped_release release;
          ch = view
                   ? render::bake_directional_view_channels(h, float(depth_texels), azimuths,
                                                            float(max_distance))
                   : render::bake_directional_channels(h, float(depth_texels), azimuths, float(max_distance));
        }
        const int nc = ch.channels();
        pyb::array_t<float> out({pyb::ssize_t(ch.height()), pyb::ssize_t(ch.width()), pyb::ssize_t(nc)});
        float* o = out.mutable_data();
        for (int j = 0; j < ch.height(); ++j)
          for (int i = 0; i < ch.width(); ++i)
            for (int k = 0; k < nc; ++k) *o++ = ch.at(i, j, k);
        return out;
      },
      "height"_a, "depth_texels"_a, "azimuths"_a = 32, "max_distance"_a = 0.0, "view"_a = false,
      "The 9 directional micro-occlusion channels of a height map, as `microshadow bake directional` bakes "
      "level 0: the weighted least-squares fit of degree <= 2 of lit * max(n . l, 0) over the upper "
      "hemisphere per texel (exact horizons along `azimuths` azimuths, ray length max_distance texels, <= 0 "
      "unlimited; n the central-difference normal). height: 2-D array (rows top to bottom) in [0, 1], each "
      "side in [8, 16384], wrapped at the edges; depth_texels: depth of the full [0, 1] range in texels. "
      "Returns float32 of shape (height, width, 9), or (height, width, 21) with view=True (the view "
      "correction's 12 slope channels follow: what directional_view_transport reads); the box mean of k x k "
      "texels is the coarse texel's own channels (mips). Runs with the GIL released on oneTBB threads "
      "(deterministic).");
}

}  // namespace msh::py

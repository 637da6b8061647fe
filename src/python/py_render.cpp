// microshadow.render / compare: the reference renderer (include/microshadow/render/renderer.h) and the
// image metrics of `microshadow compare` (RMSE and SSIM, render/image.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/render/image.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;

pyb::array_t<float> image_array(const render::Image& img) {
  pyb::array_t<float> a({pyb::ssize_t(img.height), pyb::ssize_t(img.width), pyb::ssize_t(3)});
  float* p = a.mutable_data();
  for (std::size_t i = 0; i < img.px.size(); ++i)
    p[3 * i] = img.px[i].r, p[3 * i + 1] = img.px[i].g, p[3 * i + 2] = img.px[i].b;
  return a;
}

// An image from a path (linear EXR) or an array of shape (H, W, 3) or (H, W, 4) (alpha ignored).
render::Image to_image(pyb::handle obj, const char* name) {
  if (PyUnicode_Check(obj.ptr()) || pyb::isinstance(obj, pyb::module_::import("os").attr("PathLike"))) {
    const std::string path = pyb::str(pyb::module_::import("os").attr("fspath")(obj));
    pyb::gil_scoped_release release;
    return render::read_exr(path);
  }
  const pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast> a =
      pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 3 || (a.shape(2) != 3 && a.shape(2) != 4))
    throw pyb::value_error(fmt::format("{} must be an EXR path or an array of shape (H, W, 3)", name));
  render::Image img(int(a.shape(1)), int(a.shape(0)));
  const float* p = a.data();
  const std::size_t c = std::size_t(a.shape(2));
  for (std::size_t i = 0; i < img.px.size(); ++i) img.px[i] = Rgbf(p[c * i], p[c * i + 1], p[c * i + 2]);
  return img;
}

// Every pixel finite (a NaN or Inf would make RMSE NaN and SSIM meaningless): InputError naming the pixel.
void require_finite(const render::Image& img, const std::string& what) {
  for (std::size_t i = 0; i < img.px.size(); ++i) {
    const Rgbf& q = img.px[i];
    if (!(std::isfinite(q.r) && std::isfinite(q.g) && std::isfinite(q.b)))
      throw InputError(fmt::format("{}: pixel ({}, {}) is not finite ({}, {}, {})", what,
                                   i % std::size_t(img.width), i / std::size_t(img.width), q.r, q.g, q.b));
  }
}

std::string label(pyb::handle obj, const char* fallback) {
  if (PyUnicode_Check(obj.ptr()) || pyb::isinstance(obj, pyb::module_::import("os").attr("PathLike")))
    return pyb::str(pyb::module_::import("os").attr("fspath")(obj));
  return fallback;
}

pyb::object render_scene(pyb::object scene_obj, std::optional<int> width, std::optional<int> height,
                         std::optional<int> spp, std::optional<std::string> method,
                         std::optional<uint32_t> seed, std::optional<std::string> lut, pyb::object asset_dir,
                         bool std_error) {
  // A dict is serialized to JSON; a string starting with '{' is JSON text; anything else a path.
  std::string text;
  std::filesystem::path path;
  if (pyb::isinstance<pyb::dict>(scene_obj)) {
    text = pyb::str(pyb::module_::import("json").attr("dumps")(scene_obj));
  } else {
    const std::string s = pyb::str(pyb::module_::import("os").attr("fspath")(scene_obj));
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && s[first] == '{')
      text = s;
    else
      path = s;
  }
  const std::filesystem::path assets = asset_dir.is_none()
                                           ? std::filesystem::path()
                                           : std::filesystem::path(pyb::str(asset_dir).cast<std::string>());
  render::RenderResult res;
  {
    pyb::gil_scoped_release release;
    render::Scene scene = path.empty() ? render::parse_scene(text, "<scene>", assets.empty() ? "." : assets)
                                       : render::load_scene(path, assets);
    render::Settings& s = scene.settings;
    if (width) s.width = *width;
    if (height) s.height = *height;
    if (spp) s.spp = *spp;
    if (seed) s.seed = *seed;
    if (method) s.micro_shadowing = render::micro_shadowing_from_string(*method);
    if (lut) s.lut_path = *lut;
    if (s.width < 1 || s.height < 1 || uint64_t(s.width) * s.height > (uint64_t(1) << 26))
      throw InputError(fmt::format("image size {}x{} is too large (at most 2^26 pixels)", s.width, s.height));
    if (s.spp < 1) throw InputError(fmt::format("spp must be ≥ 1, got {}", s.spp));
    const render::Renderer renderer(scene);
    if (std_error) {
      res = renderer.render_with_error();
    } else {
      res.mean = renderer.render();
    }
  }
  if (std_error) return pyb::make_tuple(image_array(res.mean), image_array(res.std_error));
  return image_array(res.mean);
}

pyb::dict compare(pyb::handle a_obj, pyb::handle b_obj, double exposure, int down, pyb::object diff) {
  if (!(exposure >= -30 && exposure <= 30))
    throw InputError(fmt::format("--exposure: Value {} not in range -30 to 30", exposure));
  if (down < 1 || down > 64)
    throw InputError(fmt::format("--downsample: Value {} not in range 1 to 64", down));
  const render::Image A = to_image(a_obj, "a"), B = to_image(b_obj, "b");
  require_finite(A, label(a_obj, "a"));
  require_finite(B, label(b_obj, "b"));
  if (A.width != B.width || A.height != B.height)
    throw InputError(fmt::format("{} is {}x{} but {} is {}x{}", label(a_obj, "a"), A.width, A.height,
                                 label(b_obj, "b"), B.width, B.height));
  double rmse = 0, ssim = 0, rmse2 = 0, ssim2 = 0;
  {
    pyb::gil_scoped_release release;
    rmse = render::rmse(A, B), ssim = render::ssim(A, B, float(exposure));
    if (down > 1) {
      const auto a2 = render::downsample(A, down), b2 = render::downsample(B, down);
      rmse2 = render::rmse(a2, b2), ssim2 = render::ssim(a2, b2, float(exposure));
    }
  }
  if (!diff.is_none()) {
    const std::string path = pyb::str(pyb::module_::import("os").attr("fspath")(diff));
    pyb::gil_scoped_release release;
    render::write_png_display(path, render::difference_image(A, B, float(exposure)));
  }
  pyb::dict j("rmse"_a = rmse, "ssim"_a = ssim);
  if (down > 1) j["rmse_downsampled"] = rmse2, j["ssim_downsampled"] = ssim2, j["downsample"] = down;
  return j;
}

}  // namespace

void register_render(pyb::module_& m) {
  m.def("render", &render_scene, "scene"_a, "width"_a = pyb::none(), "height"_a = pyb::none(),
        "spp"_a = pyb::none(), "method"_a = pyb::none(), "seed"_a = pyb::none(), "lut"_a = pyb::none(),
        "asset_dir"_a = pyb::none(), "std_error"_a = false,
        "Renders a scene with the reference CPU renderer (docs/renderer.md), as `microshadow render` does, "
        "and returns the linear RGB image as a float32 array of shape (height, width, 3), row 0 at the top. "
        "scene: a path to a scene JSON file, the JSON text itself, or a dict. width, height, spp, method "
        "(the micro-shadowing method of the scene's settings), seed and lut override the scene's settings. "
        "asset_dir: where relative texture/OBJ paths resolve (default: the JSON file's directory, or the "
        "current directory for text / dict). std_error=True returns (mean, std_error) from the scene's "
        "error_batches independent batches. Runs with the GIL released, on oneTBB threads (the image is "
        "bit-identical whatever the thread count). Bad scenes raise ValueError with the CLI's message.");
  m.def("compare", &compare, "a"_a, "b"_a, "exposure"_a = 0.0, "downsample"_a = 1, "diff"_a = pyb::none(),
        "Error of image a against the reference b, as `microshadow compare` computes it: a dict with 'rmse' "
        "(root-mean-square over pixels and channels of linear RGB) and 'ssim' (mean SSIM, Wang et al. 2004, "
        "of the luminance of the tone-mapped images at `exposure`); with downsample > 1 also "
        "'rmse_downsampled', 'ssim_downsampled' after box-downsampling. a, b: linear EXR paths or float "
        "arrays of shape (H, W, 3). diff: also write the false-colour difference PNG there (red: a brighter, "
        "blue: a darker), as --diff does.");
}

}  // namespace msh::py

// microshadow.bake_micro_shadowing_lut / load_micro_shadowing_lut: the micro-shadowing LUT baker and loader
// (include/microshadow/lut/, docs/lut.md) returning the table as a numpy array plus its sidecar as a dict.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;

// The volume as a float32 array of shape (depth, n_nl, n_vis, channels) (z = N·V [+ harmonic/roughness
// slab], y = N·L, x = Visibility or t), the table's memory layout.
pyb::array_t<float> volume_array(const io::Volume& v) {
  pyb::array_t<float> a(
      {pyb::ssize_t(v.depth), pyb::ssize_t(v.height), pyb::ssize_t(v.width), pyb::ssize_t(v.channels)});
  std::copy(v.data.begin(), v.data.end(), a.mutable_data());
  return a;
}

pyb::tuple bake(const std::string& layout_name, int harmonics, bool two_d, std::optional<int> n_vis,
                std::optional<int> n_nl, std::optional<int> n_nv, std::optional<int> n_rough,
                std::optional<std::vector<double>> roughness, std::optional<std::pair<double, double>> range,
                std::optional<int> samples, int phi_nodes, uint32_t seed, pyb::object out) {
  const lut::LutLayout layout = lut::layout_from_name(layout_name);
  const bool cone = layout == lut::LutLayout::Cone;
  if (harmonics < 0) throw InputError(fmt::format("harmonics must be ≥ 0, got {}", harmonics));
  lut::BakeOptions b = lut::default_bake_options(layout, harmonics);
  if (cone && roughness)
    throw InputError(
        "roughness (one value per channel) applies to layout 'seed'; the cone layout takes roughness_range "
        "(MIN, MAX) and n_rough");
  if (!cone && (n_rough || range)) throw InputError("n_rough and roughness_range apply to the cone layout");
  if (n_vis) b.n_vis = *n_vis;
  if (n_nl) b.n_nl = *n_nl;
  if (n_nv) b.n_nv = *n_nv;
  if (n_rough) b.n_rough = *n_rough;
  if (roughness) b.roughness = *roughness;
  if (range) b.cone.roughness_min = float(range->first), b.cone.roughness_max = float(range->second);
  if (samples) b.samples = *samples;
  b.two_d = two_d;
  b.harmonics = harmonics;
  b.phi_nodes = phi_nodes;
  b.seed = seed;
  lut::validate(b);
  std::filesystem::path path;
  if (!out.is_none()) {
    path = std::filesystem::path(pyb::str(out).cast<std::string>());
    if (io::file_format_from_path(path) != io::FileFormat::Npy)
      throw InputError(
          "out: only .npy (float32, any channel count) is written from Python; for dds/ktx2/exr/h use "
          "`microshadow bake micro-shadowing`");
    if (path.has_parent_path() && !std::filesystem::is_directory(path.parent_path()))
      throw InputError(fmt::format("--out: directory '{}' does not exist", path.parent_path().string()));
  }
  io::Volume vol;
  {
    pyb::gil_scoped_release release;
    vol = lut::bake_micro_shadowing_lut(b);
    if (!path.empty()) {
      io::write_volume(path, vol, io::FileFormat::Npy, io::PixelFormat::RGBA32Float, "micro_shadowing_lut");
      io::write_file_atomic(lut::sidecar_path(path), lut::sidecar_json(b));
    }
  }
  return pyb::make_tuple(volume_array(vol), json_to_python(lut::sidecar_json(b)));
}

pyb::tuple load(pyb::object path_obj, std::optional<std::vector<double>> roughness,
                std::optional<int> harmonics) {
  const std::filesystem::path path(pyb::str(path_obj).cast<std::string>());
  lut::MicroShadowingLut t;
  {
    pyb::gil_scoped_release release;
    t = lut::load_micro_shadowing_lut(path, roughness, harmonics);
  }
  pyb::dict meta;
  const auto side = lut::sidecar_path(path);
  std::error_code ec;
  if (std::filesystem::exists(side, ec) && !roughness && !harmonics) {
    require_regular_file(side, "LUT sidecar ");
    std::ifstream in(side);
    std::stringstream ss;
    ss << in.rdbuf();
    meta = json_to_python(ss.str());
  } else {
    meta["layout"] = lut::layout_name(t.layout);
    meta["roughness"] = t.roughness;
    meta["harmonics"] = t.harmonics;
    meta["sidecar"] = std::filesystem::exists(side, ec) ? pyb::object(pyb::str(side.string())) : pyb::none();
  }
  return pyb::make_tuple(volume_array(t.volume), meta);
}

}  // namespace

void register_lut(pyb::module_& m) {
  m.def("bake_micro_shadowing_lut", &bake, "layout"_a = "cone", "harmonics"_a = 0, "two_d"_a = false,
        "n_vis"_a = pyb::none(), "n_nl"_a = pyb::none(), "n_nv"_a = pyb::none(), "n_rough"_a = pyb::none(),
        "roughness"_a = pyb::none(), "roughness_range"_a = pyb::none(), "samples"_a = pyb::none(),
        "phi_nodes"_a = 16, "seed"_a = 1, "out"_a = pyb::none(),
        "Bakes the micro-shadowing LUT (Zurita 2026, 'Improving Direct Lighting Material Occlusion - Part "
        "2'; layouts and algorithm in docs/lut.md), as `microshadow bake micro-shadowing` does. Returns "
        "(table, sidecar): table a float32 array of shape (depth, n_nl, n_vis, channels) (cone layout: "
        "n_vis = t axis, depth = n_nv * n_rough; seed layout: channels = roughness values, depth = n_nv * "
        "(harmonics + 1)), sidecar the JSON sidecar as a dict. layout: 'cone' (default) or 'seed'; None "
        "sizes take the layout's defaults; harmonics > 0 bakes the azimuth-aware table; two_d the N.V = 1 "
        "slice only. out: optional .npy path, written atomically with its sidecar <out>.json (readable by "
        "load_micro_shadowing_lut, the CLI's --lut and the renderer). Bad options raise ValueError with "
        "the CLI's message. Runs with the GIL released, on oneTBB threads (bit-identical for any thread "
        "count).");
  m.def("load_micro_shadowing_lut", &load, "path"_a, "roughness"_a = pyb::none(), "harmonics"_a = pyb::none(),
        "Loads a baked micro-shadowing LUT (any format the CLI reads: dds, ktx2, exr, npy) and its sidecar "
        "<path>.json. Returns (table, sidecar): table as in bake_micro_shadowing_lut, sidecar the JSON "
        "sidecar as a dict (without a sidecar: the defaults the loader assumes, layout 'seed', roughness "
        "per channel, harmonics 0, and 'sidecar': None). roughness / harmonics override the sidecar (seed "
        "layout only; the dict then holds the values used). An unreadable or inconsistent file raises "
        "ValueError with the CLI's message.");
}

}  // namespace msh::py

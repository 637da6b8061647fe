// Table loading, JSON sidecar, and the cached default tables. See micro_shadowing_loader.h.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

namespace msh::lut {

std::filesystem::path sidecar_path(const std::filesystem::path& table) {
  std::filesystem::path p = table;
  p += ".json";
  return p;
}

// The shortest decimal that reads back as the same float (0.1f → 0.1, not 0.10000000149011612).
double short_float(float f) { return std::stod(fmt::format("{}", f)); }

namespace {
constexpr Named<LutLayout> kLayouts[] = {{LutLayout::Seed, "seed"}, {LutLayout::Cone, "cone"}};
}  // namespace

const char* layout_name(LutLayout l) { return name_of<LutLayout>(kLayouts, l); }

LutLayout layout_from_name(const std::string& name) {
  return value_of<LutLayout>(kLayouts, name, "LUT layout");
}

std::string sidecar_json(const BakeOptions& o) {
  nlohmann::json j;
  j["format"] = "microshadow micro-shadowing LUT";
  j["layout"] = layout_name(o.layout);
  j["harmonics"] = o.harmonics;
  j["size_n_dot_l"] = o.n_nl;
  j["size_n_dot_v"] = o.two_d ? 1 : o.n_nv;
  if (o.layout == LutLayout::Cone) {
    j["layout_description"] =
        "x = t (cone half-angle relative to the light, t = 0 at 2V + N.L = 1, t = 1 at V = 1), y = N.L "
        "coordinate, z = N.V coordinate + n_nv * roughness slab, channel h = cos(h phi) coefficient; see "
        "docs/lut.md";
    j["size_t"] = o.n_vis;
    j["roughness_slabs"] = o.n_rough;
    j["roughness_range"] = {short_float(o.cone.roughness_min), short_float(o.cone.roughness_max)};
    j["roughness_power"] = short_float(o.cone.roughness_power);
    j["warp_scale"] = short_float(o.cone.warp_scale);
    j["nl_warp"] = o.cone.nl_warp;
    j["nv_warp"] = o.cone.nv_warp;
    j["nv_scale"] = short_float(o.cone.nv_scale);
    j["top_scale"] = short_float(o.cone.top_scale);
  } else {
    j["layout_description"] =
        "x = Visibility, y = N·L, z = N·V (+ harmonic slab), channel = roughness; texel i of n = i/(n-1)";
    j["size_visibility"] = o.n_vis;
    j["roughness"] = o.roughness;
  }
  j["two_d"] = o.two_d;
  j["samples"] = o.samples;
  j["phi_nodes"] = o.phi_nodes;
  j["seed"] = o.seed;
  return j.dump(2) + "\n";
}

namespace {
// Sidecar fields, strictly typed. nlohmann's get<int>() of a floating-point value converts it with a cast,
// undefined beyond int's range (fuzzing: "harmonics": 4e45); get<float>() of 1e300 gives infinity.
int sidecar_int(const nlohmann::json& j, const char* key) {
  const nlohmann::json& v = j.at(key);
  if (!v.is_number_integer()) throw InputError(fmt::format("{} must be an integer", key));
  const std::int64_t x = v.get<std::int64_t>();
  if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
    throw InputError(fmt::format("{} = {} is out of range", key, x));
  return int(x);
}
float finite_float(const nlohmann::json& v, const char* key) {
  if (!v.is_number()) throw InputError(fmt::format("{} must be a number", key));
  const double x = v.get<double>();
  if (!(std::abs(x) <= double(std::numeric_limits<float>::max())))
    throw InputError(fmt::format("{} = {} is not a finite float", key, x));
  return float(x);
}
float sidecar_float(const nlohmann::json& j, const char* key) { return finite_float(j.at(key), key); }
}  // namespace

MicroShadowingLut load_micro_shadowing_lut(const std::filesystem::path& path,
                                           std::optional<std::vector<double>> roughness,
                                           std::optional<int> harmonics) {
  MicroShadowingLut lut;
  lut.volume = io::read_volume(path);
  std::vector<double> r(kDefaultRoughness.begin(), kDefaultRoughness.end());
  int h = 0;
  const auto side = sidecar_path(path);
  const io::Volume& vol = lut.volume;
  if (std::filesystem::exists(side)) {
    require_regular_file(side, "LUT sidecar ");
    std::ifstream in(side);
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(in);
      // Sidecars written before the cone layout hold a description string under "layout": the seed layout.
      const std::string name = j.value("layout", std::string("seed"));
      lut.layout = name.rfind("x = Visibility", 0) == 0 ? LutLayout::Seed : layout_from_name(name);
      h = sidecar_int(j, "harmonics");
      if (lut.layout == LutLayout::Cone) {
        lut.n_rough = sidecar_int(j, "roughness_slabs");
        const nlohmann::json& range = j.at("roughness_range");
        if (!range.is_array() || range.size() != 2) throw InputError("roughness_range must hold 2 values");
        lut.cone.roughness_min = finite_float(range[0], "roughness_range");
        lut.cone.roughness_max = finite_float(range[1], "roughness_range");
        lut.cone.roughness_power = sidecar_float(j, "roughness_power");
        lut.cone.warp_scale = sidecar_float(j, "warp_scale");
        lut.cone.nl_warp = sidecar_int(j, "nl_warp");
        lut.cone.nv_warp = sidecar_int(j, "nv_warp");
        lut.cone.nv_scale = sidecar_float(j, "nv_scale");
        lut.cone.top_scale = sidecar_float(j, "top_scale");
      } else {
        r = j.at("roughness").get<std::vector<double>>();
      }
    } catch (const std::exception& e) {
      throw InputError(fmt::format("'{}': not a valid LUT sidecar ({})", side.string(), e.what()));
    }
    // Sizes recorded by the baker must match the file (a sidecar next to another table is an error).
    auto check = [&](const char* key, int actual) {
      if (j.contains(key) && j[key].is_number_integer() && j[key].get<std::int64_t>() != actual)
        throw InputError(fmt::format("'{}': sidecar {} = {} but '{}' has {}", side.string(), key,
                                     j[key].get<std::int64_t>(), path.string(), actual));
    };
    check(lut.layout == LutLayout::Cone ? "size_t" : "size_visibility", vol.width);
    check("size_n_dot_l", vol.height);
    if (lut.layout == LutLayout::Cone) {
      check("roughness_slabs", lut.n_rough > 0 && vol.depth % lut.n_rough == 0 ? lut.n_rough : -1);
      if (lut.n_rough > 0) check("size_n_dot_v", vol.depth / lut.n_rough);
    } else {
      check("size_n_dot_v", vol.depth / std::max(1, h + 1));
    }
  } else if (vol.channels != 4 && !roughness) {
    throw InputError(fmt::format("'{}' has {} channels and no sidecar '{}': give the roughness per channel",
                                 path.string(), vol.channels, side.string()));
  }
  if (lut.layout == LutLayout::Cone) {
    if (roughness)
      throw InputError("a cone-layout LUT has roughness slabs (from its sidecar), not roughness per channel");
    if (harmonics) h = *harmonics;
    lut.harmonics = h;
    (void)lut.view();  // validates the shape and the parameters
    return lut;
  }
  if (roughness) r = *roughness;
  if (harmonics) h = *harmonics;
  for (std::size_t i = 0; i < r.size(); ++i)
    if (!(r[i] >= 0.0 && r[i] <= 1.0) || (i > 0 && !(r[i] > r[i - 1])))
      throw InputError("LUT roughness values must be strictly increasing in [0, 1]");
  lut.roughness = r;
  lut.harmonics = h;
  (void)lut.view();  // validates the shape
  return lut;
}

std::shared_ptr<const MicroShadowingLut> default_micro_shadowing_lut(bool two_d, int harmonics,
                                                                     LutLayout layout) {
  static std::mutex mutex;
  static std::map<std::tuple<bool, int, int>, std::shared_ptr<const MicroShadowingLut>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[{two_d, harmonics, int(layout)}];
  if (!slot) {
    BakeOptions o = default_bake_options(layout, harmonics);
    o.two_d = two_d;
    auto lut = std::make_shared<MicroShadowingLut>();
    lut->volume = bake_micro_shadowing_lut(o);
    lut->layout = layout;
    lut->roughness = o.roughness;
    lut->harmonics = harmonics;
    lut->n_rough = o.n_rough;
    lut->cone = o.cone;
    slot = lut;
  }
  return slot;
}

}  // namespace msh::lut

// Table loading, JSON sidecar, and the cached default tables. See micro_shadowing_loader.h.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/micro_shadowing_loader.h>

#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

namespace msh::lut {

std::filesystem::path sidecar_path(const std::filesystem::path& table) {
  std::filesystem::path p = table;
  p += ".json";
  return p;
}

std::string sidecar_json(const BakeOptions& o) {
  nlohmann::json j;
  j["format"] = "microshadow micro-shadowing LUT";
  j["layout"] =
      "x = Visibility, y = N·L, z = N·V (+ harmonic slab), channel = roughness; texel i of n = i/(n-1)";
  j["roughness"] = o.roughness;
  j["harmonics"] = o.harmonics;
  j["size_visibility"] = o.n_vis;
  j["size_n_dot_l"] = o.n_nl;
  j["size_n_dot_v"] = o.two_d ? 1 : o.n_nv;
  j["two_d"] = o.two_d;
  j["samples"] = o.samples;
  j["phi_nodes"] = o.phi_nodes;
  j["seed"] = o.seed;
  return j.dump(2) + "\n";
}

MicroShadowingLut load_micro_shadowing_lut(const std::filesystem::path& path,
                                           std::optional<std::vector<double>> roughness,
                                           std::optional<int> harmonics) {
  MicroShadowingLut lut;
  lut.volume = io::read_volume(path);
  std::vector<double> r(kDefaultRoughness.begin(), kDefaultRoughness.end());
  int h = 0;
  const auto side = sidecar_path(path);
  if (std::filesystem::exists(side)) {
    std::ifstream in(side);
    try {
      const nlohmann::json j = nlohmann::json::parse(in);
      r = j.at("roughness").get<std::vector<double>>();
      h = j.at("harmonics").get<int>();
    } catch (const std::exception& e) {
      throw InputError(fmt::format("'{}': not a valid LUT sidecar ({})", side.string(), e.what()));
    }
  } else if (lut.volume.channels != 4 && !roughness) {
    throw InputError(fmt::format("'{}' has {} channels and no sidecar '{}': give the roughness per channel",
                                 path.string(), lut.volume.channels, side.string()));
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

std::shared_ptr<const MicroShadowingLut> default_micro_shadowing_lut(bool two_d, int harmonics) {
  static std::mutex mutex;
  static std::map<std::pair<bool, int>, std::shared_ptr<const MicroShadowingLut>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[{two_d, harmonics}];
  if (!slot) {
    BakeOptions o;
    o.two_d = two_d;
    o.harmonics = harmonics;
    auto lut = std::make_shared<MicroShadowingLut>();
    lut->volume = bake_micro_shadowing_lut(o);
    lut->roughness = o.roughness;
    lut->harmonics = harmonics;
    slot = lut;
  }
  return slot;
}

}  // namespace msh::lut

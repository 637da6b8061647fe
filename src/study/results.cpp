// Results of the study's cells into its files (see study/study.h): results.json, results.csv, summary.md,
// area_summary.md, study.html, timing.json.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/study/study.h>

#include <cmath>

#include "study_internal.h"

namespace msh::study {

using namespace msh::study::detail;
using json = nlohmann::json;

namespace {

std::string csv_header() {
  std::string h =
      "material,shape,scale,view,view_azimuth,light,light_type,elevation,azimuth,method,ms_normal,roughness,"
      "component,gt_mean_whole";
  for (const char* m :
       {"bias", "bias_stderr", "rmse_footprint", "rmse_footprint_floor", "rmse", "rmse_stderr"})
    for (const char* r : kRegionName) h += fmt::format(",{}_{}", m, r);
  return h + ",ssim\n";
}
std::string csv_value(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number()) return fmt::format("{:.9g}", v.get<double>());
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}
std::string csv_line(const json& r) {
  std::string s;
  for (const char* k : {"material", "shape", "scale", "view", "view_azimuth", "light", "light_type",
                        "elevation", "azimuth", "method", "ms_normal", "roughness", "component"})
    s += csv_value(r[k]) + ",";
  s += csv_value(r["gt_mean"]["whole"]);
  for (const char* m :
       {"bias", "bias_stderr", "rmse_footprint", "rmse_footprint_floor", "rmse", "rmse_stderr"})
    for (const char* reg : kRegionName) {
      // Two appends, not "," + value: GCC 12 inlines that into a false -Wrestrict warning here.
      s += ',';
      s += csv_value(r[m][reg]);
    }
  return s + "," + csv_value(r["ssim"]) + "\n";
}

json config_json(const StudyConfig& c) {
  // "materials": every material of the rows (the report's per-material tables), the user's maps last.
  std::vector<std::string> names = c.materials;
  json user = json::array();
  for (const UserMaterial& u : c.user_materials) {
    names.push_back(u.name);
    user.push_back(
        {{"name", u.name}, {"height", u.height.filename().string()}, {"depth_texels", u.depth_texels}});
  }
  return {{"name", c.name},
          {"materials", names},
          {"user_materials", user},
          {"fine_size", c.fine_size},
          {"ao_rays", c.ao_rays},
          {"directional_azimuths", c.directional_azimuths},
          {"scales", c.scales},
          {"shapes", c.shapes},
          {"elevations", c.elevations},
          {"azimuths", c.azimuths},
          {"point_light", c.point_light},
          {"sphere_light", c.sphere_light},
          {"near_lights", c.near_lights},
          {"near_light_footprints", c.near_light_footprints},
          {"image_size", c.image_size},
          {"views", c.views},
          {"view_azimuths", c.view_azimuths},
          {"max_windows", c.max_windows},
          {"sweep",
           {{"views", c.sweep_views},
            {"view_azimuths", c.sweep_view_azimuths},
            {"elevations", c.sweep_elevations},
            {"azimuths", c.sweep_azimuths},
            {"scales", c.sweep_scales},
            {"terms", c.sweep_terms},
            {"gt_spp", c.sweep_gt_spp},
            {"gt_max_spp", c.sweep_gt_max_spp}}},
          {"method_spp", c.method_spp},
          {"vndf_samples", c.vndf_samples},
          {"area_samples", c.area_samples},
          {"gt_spp", c.gt_spp},
          {"gt_max_spp", c.gt_max_spp},
          {"gt_rule", c.gt_rule == StudyConfig::GtRule::Bias ? "bias" : "full"},
          {"footprint", c.footprint},
          {"delta_bias", c.delta_bias},
          {"delta_rmse", c.delta_rmse},
          {"widened", c.widened},
          {"normal_ablation", c.normal_ablation},
          {"directional_encoding", render::directional_encoding_name(c.directional_encoding)},
          {"terms", c.terms},
          {"seed", c.seed}};
}
json config_json_area(const StudyConfig& c) {
  json j = config_json(c);
  if (area_section(c))
    j["area"] = {{"radii_deg", c.area_radii_deg},
                 {"elevations", c.area_elevations},
                 {"planar_radii_deg", c.area_planar_radii_deg},
                 {"planar_elevation", c.area_planar_elevation},
                 {"azimuth", c.area_azimuth},
                 {"terms", c.area_terms},
                 {"area_ms", c.area_ms_modes}};
  return j;
}

}  // namespace

void detail::scrub(json& j) {
  if (j.is_object() || j.is_array()) {
    for (auto& v : j) scrub(v);
  } else if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    j = nullptr;
  }
}

json aggregate_results(const StudyPlan& plan, const std::vector<CellResult>& cells) {
  const StudyConfig& cfg = plan.config;
  json gt_rows = json::array(), rows = json::array(), images = json::array(), area_rep = json::array();
  for (const CellResult& c : cells) {
    gt_rows.push_back(c.ground_truth);
    for (const json& r : c.rows) rows.push_back(r);
    for (const json& i : c.images) images.push_back(i);
    for (const json& a : c.area_representative) area_rep.push_back(a);
  }
  json results = {
      {"config", config_json_area(cfg)}, {"ground_truth", gt_rows}, {"rows", rows}, {"images", images}};
  scrub(results);
  results["summary"] = summarize(results["rows"], cfg);
  if (area_section(cfg)) {
    results["area_summary"] = summarize_area(results["rows"]);
    results["area_representative"] = area_rep;
    scrub(results["area_representative"]);
  }
  return results;
}

void write_results(const json& results, const std::filesystem::path& out) {
  std::string csv = csv_header();
  for (const auto& r : results["rows"]) csv += csv_line(r);
  io::write_file_atomic(out / "results.json", results.dump(1) + "\n");
  io::write_file_atomic(out / "results.csv", csv);
  io::write_file_atomic(out / "summary.md", summary_markdown(results));
  if (results.contains("area_summary"))
    io::write_file_atomic(out / "area_summary.md", area_summary_markdown(results));
  write_study_html(results, out);
}

json aggregate_timing(const std::vector<CellResult>& cells, const json& preparation, double wall_seconds,
                      double cpu_seconds) {
  double t_gt = 0, t_methods = 0, ray_seconds = 0;
  uint64_t rays = 0;
  std::map<std::string, double> variant_cpu;
  for (const CellResult& c : cells) {
    t_gt += c.ground_truth_seconds;
    t_methods += c.methods_seconds;
    rays += c.ground_truth_rays;
    ray_seconds += c.ground_truth_ray_seconds;
    for (const auto& [label, s] : c.variant_cpu_seconds) variant_cpu[label] += s;
  }
  json timing = preparation;
  timing["ground_truth_seconds"] = t_gt;
  timing["methods_seconds"] = t_methods;
  timing["total_seconds"] = wall_seconds;
  timing["total_cpu_seconds"] = cpu_seconds;
  timing["ground_truth_rays"] = rays;
  timing["term_cpu_seconds"] = variant_cpu;
  timing["ground_truth_rays_per_second"] = ray_seconds > 0 ? double(rays) / ray_seconds : 0.0;
  return timing;
}

}  // namespace msh::study

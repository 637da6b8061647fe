// The multiscale study (docs/study.md): a fine height field is the real surface; the texture set an engine
// would use is derived from it at 1/k resolution; the ground truth ray-traces the fine geometry, every
// micro-shadowing term renders the coarse set with the same camera, and the study measures each term's
// mean-radiance bias and footprint RMSE against the ground truth, with the ground truth's noise floor.
#pragma once

#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/multiscale.h>
#include <microshadow/render/scene.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace msh::study {

// A user's height map in the study (`study --height FILE --depth D`, `study --material DIR`): its fine
// texture set is texture_set_from_height(load_height_map(height), depth_texels) with the same bake options
// as the procedural kinds. The map must be square; its side is that material's fine size.
struct UserMaterial {
  std::string name;              // in the results (the file's stem, or the gen-material folder's name)
  std::filesystem::path height;  // 16-bit PNG or EXR, grey, values in [0, 1] (render::load_height_map)
  float depth_texels = 0;        // depth of the full [0, 1] range in texels, in (0, 10000]
};

// A gen-material folder (height.png and material.json with height_texels) as a user material named after
// the folder. InputError with one line naming the folder if either is missing or unreadable.
UserMaterial user_material_from_folder(const std::filesystem::path& dir);

struct StudyConfig {
  std::string name = "full";
  // generate_texture_set kinds: the micro-geometry ones (plaster), then the ones with relief.
  std::vector<std::string> materials{"plaster", "bark", "gravel", "rock", "brick", "cobble"};
  // The user's height maps, studied after the procedural kinds (materials may then be empty).
  std::vector<UserMaterial> user_materials;
  int fine_size = 2048;  // fine height field, texels per side
  int ao_rays = 16;      // micro-occlusion bake: azimuths per fine texel (each exact in elevation)
  // Directional micro-occlusion bake (render/directional_bake.h): azimuths per fine texel; baked only when a
  // term reads it.
  int directional_azimuths = 32;
  std::vector<int> scales{1, 4, 16};         // k: coarse set = fine / k
  std::vector<std::string> shapes{"plane"};  // plane, cylinder (displaced; its ground truth uses Embree)
  std::vector<double> elevations{5, 10, 25, 45, 70};  // directional lights (degrees above the plane)
  std::vector<double> azimuths{0, 90};                // degrees from +u (the texture's x axis)
  bool point_light = true, sphere_light = true;
  int image_size = 64;         // pixels per side at every scale; a pixel covers k × k fine texels (across)
  double view_elevation = 60;  // camera elevation above the plane, degrees (looking along +v)
  int method_spp = 4;          // samples per pixel of the approximations
  int vndf_samples = 64;       // generic-vndf samples per light
  int area_samples = 16;       // sphere light: area samples per shading point (ground truth and terms)
  int gt_spp = 64;           // ground truth: first round's samples per pixel (doubled until the floor is met)
  int gt_max_spp = 512;      // ... or until this many
  int footprint = 4;         // rmse_footprint block: footprint × footprint pixels
  double delta_bias = 0.01;  // smallest bias difference the ranking resolves
  double delta_rmse = 0.01;  // smallest rmse_footprint difference it resolves, relative to the GT mean
  // The terms rendered on the coarse sets: methods of the runtime registry
  // (occlusion/runtime/micro_shadowing_methods.h); default: the registry's study list.
  std::vector<std::string> terms = occlusion::micro_shadowing_study_methods();
  bool widened = true;          // also render every term with the variance-widened coarse roughness
  bool normal_ablation = true;  // also render the N·L terms with the unperturbed normal
  std::vector<std::string> featured_lights{"dir-el10-az0", "dir-el45-az0"};  // lights shown as images
  std::string lut_path;  // lut3d / lut2d table (empty: the LUT module's default)
  // Area-light section (docs/area-lights.md §8; `microshadow study --area-lights`): sphere lights of
  // angular radius area_radii_deg at each elevation of area_elevations (a sphere whose cone would reach below
  // 5° above the tangent plane is skipped), disk and rect lights of angular radius area_planar_radii_deg at
  // area_planar_elevation facing the view's centre, all at azimuth area_azimuth; every term of area_terms
  // rendered with each mode of area_ms_modes (render::AreaMs; none and ao with "sampled" only: their term
  // does not depend on the direction). Rows carry "area_ms" and "light_radius_deg"; results.json gains
  // "area_summary" and the run writes area_summary.md. Empty area_radii_deg and area_planar_radii_deg: off.
  std::vector<double> area_radii_deg;
  std::vector<double> area_elevations;
  std::vector<double> area_planar_radii_deg;
  double area_planar_elevation = 45;
  double area_azimuth = 90;
  std::vector<std::string> area_terms{"none", "ao", "reference", "generic-vndf", "lut3d"};
  std::vector<std::string> area_ms_modes{"sampled", "representative", "integrated"};
  // When set, fine texture sets are cached there (float32 NPY, keyed by kind, size, bake azimuths, seed) and
  // reused by later runs; results are identical either way.
  std::filesystem::path material_cache;
  uint32_t seed = 1;
};

// `--quick` (make demo) and the full study.
StudyConfig quick_config();
StudyConfig full_config();
// The area-light study (docs/area-lights.md): plaster, plane, k >= 4, no directional lights; sphere
// lights of 1–40° angular radius, a disk and a rect; representative vs integrated vs sampled micro-shadowing.
StudyConfig area_config(bool quick);

// Progress lines (stderr in the CLI).
using Log = std::function<void(const std::string&)>;

// Runs the study and writes out_dir/results.json (config, ground-truth rows, method rows, summary),
// results.csv (one line per method row), summary.md (the verdict tables), study.html and images/*.png, and
// timing.json (wall times; results.json holds no times, so it is bit-identical across runs and thread
// counts). Returns results.json's content. InputError on a bad configuration, a bad user height map (missing,
// unreadable, not square, a side the scales do not divide or narrower than the view, a bad depth: checked
// before any work) or an unwritable directory.
nlohmann::json run_study(const StudyConfig& cfg, const std::filesystem::path& out_dir, const Log& log = {});

// The verdict tables: from the method rows of results.json (used by run_study; exposed for tests).
nlohmann::json summarize(const nlohmann::json& rows, const StudyConfig& cfg);

// Writes study.html from results.json's content (images referenced relative to out_dir).
void write_study_html(const nlohmann::json& results, const std::filesystem::path& out_dir);
// Markdown verdict tables (summary.md).
std::string summary_markdown(const nlohmann::json& results);

// The area-light section (src/study/area_report.cpp): per {material, scale, light, component}, every
// {method, area_ms} with its bias, bias standard error, footprint RMSE / GT mean and its floor (rows without
// "area_ms" are skipped); and its markdown tables (area_summary.md).
nlohmann::json summarize_area(const nlohmann::json& rows);
std::string area_summary_markdown(const nlohmann::json& results);

}  // namespace msh::study

// The multiscale study (docs/study.md): a fine height field is the real surface; the texture set an engine
// would use is derived from it at 1/k resolution; the ground truth ray-traces the fine geometry, every
// micro-shadowing term renders the coarse set with the same camera, and the study measures each term's
// mean-radiance bias and footprint RMSE against the ground truth, with the ground truth's noise floor.
#pragma once

#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/image.h>
#include <microshadow/render/multiscale.h>
#include <microshadow/render/scene.h>
#include <microshadow/study/metrics.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
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
  std::vector<double> azimuths{0, 90};  // light azimuths, degrees from +u (the texture's x axis) towards +v
  bool point_light = true, sphere_light = true;
  // Lights near the surface, per scale k: a point light and a sphere light (radius one footprint) at
  // near_light_footprints footprints (footprint · k fine texels each) from the view's centre, elevation 30°,
  // azimuth 45°, so that the direction to the light turns across the view (rows: point-near, sphere-near).
  bool near_lights = false;
  double near_light_footprints = 4;
  // The camera (orthographic): each view angle off the mean surface's normal (degrees, [0, 89]) at each view
  // azimuth (degrees from +u towards +v, of the direction to the camera; 270 = the camera at -v looking
  // along +v). A pixel covers k fine texels across and k / cos(view) along the view; the image is
  // image_size pixels across (at most the texture's fine_size / k) and, to measure the same texture area at
  // every view, image_size · min(1, cos(view) / cos 30°) rows (a multiple of footprint, at least one).
  std::vector<double> views{30};
  std::vector<double> view_azimuths{270};
  int image_size = 64;  // pixels across at every scale
  // Windows: where the view covers a quarter of the texture or less (fine_size / (image_size · k) >= 4,
  // e.g. k = 1-8 at 2048²), the image is split into n × n windows of equal size spread over the texture by a
  // quasirandom sequence (n = the footprints across, at most max_windows; planes only: 16 × 16 windows of
  // one footprint at the default 64 pixels), so that the ratio is a mean over many regions, never one shadow
  // or one phase of a periodic pattern.
  int max_windows = 16;
  // The view sweep: a second grid of cells (views × view azimuths × light elevations × light azimuths ×
  // scales) rendered with sweep_terms only (no ablations); cells that the main grid already has are not
  // repeated (their rows come from the main grid). Empty sweep_views: no sweep.
  std::vector<double> sweep_views, sweep_view_azimuths{270}, sweep_elevations, sweep_azimuths;
  std::vector<int> sweep_scales;
  std::vector<std::string> sweep_terms;
  int method_spp = 4;     // samples per pixel of the approximations
  int vndf_samples = 64;  // generic-vndf samples per light
  int area_samples = 16;  // sphere light: area samples per shading point (ground truth and terms)
  int gt_spp = 64;        // ground truth: first round's samples per pixel (doubled until the floor is met)
  int gt_max_spp = 512;   // ... or until this many
  // The ground truth's stopping rule: Full = for every component carrying at least 2 % of the total, the
  // whole view's bias floor below delta_bias / 4 and its footprint-RMSE floor below delta_rmse / 4 of the
  // mean; Bias = the bias floors of the total and the diffuse only (what the view sweep and the small
  // default set of the user's maps report: their footprint RMSE keeps its floor in the rows).
  enum class GtRule { Full, Bias };
  GtRule gt_rule = GtRule::Full;
  // The view sweep's cells: the Bias rule from sweep_gt_spp up to sweep_gt_max_spp.
  int sweep_gt_spp = 32, sweep_gt_max_spp = 256;
  int footprint = 4;         // rmse_footprint block: footprint × footprint pixels
  double delta_bias = 0.01;  // smallest bias difference the ranking resolves
  double delta_rmse = 0.01;  // smallest rmse_footprint difference it resolves, relative to the GT mean
  // The terms rendered on the coarse sets: methods of the runtime registry
  // (occlusion/runtime/micro_shadowing_methods.h); default: the registry's study list. A method that reads
  // the directional channels may name a compact form, "method@form" (render/directional_codec.h, e.g.
  // "directional-view@pca8"): the coarse level is then what that form stores (the code fitted to the fine
  // channels; encoded, quantised, decoded), in place of directional_encoding's; "@unorm8" and "@bc4" store
  // every channel on its own (render::DirectionalEncoding).
  std::vector<std::string> terms = occlusion::micro_shadowing_study_methods();
  bool widened = true;          // also render every term with the variance-widened coarse roughness
  bool normal_ablation = true;  // also render the N·L terms with the unperturbed normal
  std::vector<std::string> featured_lights{"dir-el10-az0", "dir-el45-az0"};  // lights shown as images
  std::string lut_path;  // lut3d / lut2d table (empty: the LUT module's default)
  // How the coarse sets store the directional channels (render::store_directional_channels, between the fine
  // level's ranges): Float, or Unorm8 / Bc4 to rank what an engine samples from gen-material's 8-bit or BC4
  // mips. The ground truth does not read them.
  render::DirectionalEncoding directional_encoding = render::DirectionalEncoding::Float;
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
//
// It is the composition of the stages below: plan_study, a CellRunner running every cell of the plan in
// order, write_featured_images after each cell, then aggregate_results, write_results and aggregate_timing.
nlohmann::json run_study(const StudyConfig& cfg, const std::filesystem::path& out_dir, const Log& log = {});

// ---- Plan: what the study renders ----

// A light of a cell, placed in the frame of the shape's view centre.
struct StudyLight {
  std::string name;  // in the rows: dir-el{E}-az{A}, point, sphere; area section: {type}-r{R}-el{E}
  std::string type;  // directional, point, sphere, disk, rect
  render::Light light;
  double elevation = 0, azimuth = 0;  // degrees, of the direction to the light at the view's centre
  double radius_deg = 0;              // area-light section: angular radius seen from the view's centre
};

// A term variant: a runtime-registry method, rendered on the coarse set with these options.
struct StudyVariant {
  std::string term;
  bool smooth_normal = false;  // N·L and N·V of the term from the unperturbed normal (rows: ms_normal)
  render::CoarseRoughness roughness = render::CoarseRoughness::Base;
  render::AreaMs area_ms = render::AreaMs::Sampled;  // area-light section only
};

// A material of the plan: a procedural kind, or a user's height map (loaded and checked by plan_study).
struct StudyMaterial {
  std::string name;             // the rows' "material"
  int fine_size = 0;            // fine texels per side: StudyConfig::fine_size, or the user map's side
  render::Texture user_height;  // the user's map; empty for a procedural kind
  float depth_texels = 0;       // the user map's depth (UserMaterial::depth_texels)
  bool user() const { return !user_height.empty(); }
};

// A cell's camera: its direction and the windows of its image (StudyConfig's views and windows comments).
struct StudyView {
  double view = 30, view_azimuth = 270;  // degrees off the normal; azimuth of the direction to the camera
  int windows = 1;                       // per side
  int width = 64, height = 64;           // pixels of one window (the image: windows × windows of them)
  double extent = 0;  // how far the windows reach on the plane: tiles from the view's centre along u or v
  int image_width() const { return windows * width; }
  int image_height() const { return windows * height; }
};

// One cell: a ground truth and every variant of its scale, measured against it.
struct StudyCell {
  std::size_t material = 0;  // index into StudyPlan::materials
  std::string shape;         // plane, cylinder
  int scale = 1;             // k
  StudyView view;
  StudyLight light;
  bool sweep = false;  // a cell of the view sweep: StudyPlan::sweep_variants
};

struct StudyPlan {
  StudyConfig config;
  std::vector<StudyMaterial> materials;  // the procedural kinds, then the user's maps
  // material → shape → scale → light, the order of results.json's rows (and the order in which a CellRunner
  // builds each shared state once).
  std::vector<StudyCell> cells;
  std::map<int, std::vector<StudyVariant>> variants;  // per scale: what every cell of that scale renders
  std::map<int, std::vector<StudyVariant>> sweep_variants;  // per scale, the sweep's cells
  const std::vector<StudyVariant>& variants_of(const StudyCell& c) const {
    return (c.sweep ? sweep_variants : variants).at(c.scale);
  }
};

// The camera of a cell of `shape` at view angle `view` (degrees off the normal), view azimuth and scale k
// for a fine texture of fine_size texels (StudyConfig's views and windows comments).
StudyView study_view(const StudyConfig& c, const std::string& shape, int fine_size, double view,
                     double view_azimuth, int k);

// A term "method@form" split into its method and compact form ("" when it names none).
std::pair<std::string, std::string> split_study_term(const std::string& term);

// Validates the configuration and loads and checks the user's height maps (the InputErrors of run_study,
// before any work), then enumerates the cells and the variants.
StudyPlan plan_study(const StudyConfig& cfg);

// ---- Measure: one variant against the ground truth ----

// The regions a cell is measured over: the texture's rough half and smooth half (pixels near a boundary
// belong to neither) and the whole shape (pixels that miss it belong to no region).
struct Regions {
  Mask rough, smooth, whole;
};

// A cell's image per component (0 total, 1 diffuse, 2 specular), linear, and its per-channel standard error
// (the ground truth's; a term's image has none).
struct ComponentImages {
  render::Image img[3], se[3];
};

// The ground truth as the metrics read it: its images, and per component the luminance and the luminance's
// standard error.
struct GroundTruth {
  ComponentImages images;
  Plane lum[3], lum_se[3];
};
GroundTruth make_ground_truth(ComponentImages images);

// A variant's measured fields per component (total, diffuse, specular) against the ground truth: gt_mean,
// bias, bias_stderr, rmse_footprint, rmse_footprint_floor, rmse, rmse_stderr (each per region: rough,
// smooth, whole; NaN where a region has no signal) and ssim (null when undefined). footprint: the
// rmse_footprint block side in pixels.
std::array<nlohmann::json, 3> measure_variant(const ComponentImages& variant, const GroundTruth& gt,
                                              const Regions& regions, int footprint);

// ---- Cell: the ground truth and every variant of one (material, shape, scale, light) ----

// An image of a featured light (StudyConfig::featured_lights), to be written under the output directory.
struct FeaturedImage {
  std::string file;  // relative to the output directory: images/{material}_{shape}_k{k}_{light}_{method}...
  render::Image image;
  float exposure = 0;    // display exposure (the ground truth's), for a linear image
  bool display = false;  // already display-encoded (the difference images): written without tone mapping
};

// What one cell produced: results.json's entries for it and its cost. The JSON holds no NaN (null instead).
struct CellResult {
  nlohmann::json ground_truth;          // its "ground_truth" row: spp, rounds, floors_met, components, rays
  nlohmann::json rows;                  // its "rows": one per variant and component
  nlohmann::json images;                // its "images" entries (featured lights only)
  nlohmann::json area_representative;   // area-light section: the representative point's own error
  std::vector<FeaturedImage> featured;  // the pixels of `images`
  // Cost, for timing.json only.
  double ground_truth_seconds = 0, methods_seconds = 0;
  uint64_t ground_truth_rays = 0;
  double ground_truth_ray_seconds = 0;                // the renderer's own time for those rays
  std::map<std::string, double> variant_cpu_seconds;  // by variant label (+ " (area light)")
};

// Runs cells of a plan. The state they share is built when a cell needs it and kept for the next cells:
// the fine texture set of the material (generated, or read from StudyConfig::material_cache), the
// ground-truth renderer of the material × shape (the fine geometry's acceleration structure: tens of seconds
// for a displaced cylinder at 2048²), and the coarse scenes, camera and regions of the scale. Cells in plan
// order build each once; a cell of another material, shape or scale rebuilds from that level down. A cell's
// result does not depend on which cells ran before it. The plan must outlive the runner.
class CellRunner {
 public:
  explicit CellRunner(const StudyPlan& plan, Log log = {});
  ~CellRunner();
  CellRunner(const CellRunner&) = delete;
  CellRunner& operator=(const CellRunner&) = delete;

  // The ground truth (diffuse and specular alone, in rounds that double the samples until the noise floors
  // are met or gt_max_spp) and every variant of the cell's scale, measured (measure_variant).
  CellResult run(const StudyCell& cell);

  // What building the shared state cost: {"generate_seconds": total, "materials": {name:
  // {"generate_seconds", "gt_build_seconds_{shape}"}}}.
  const nlohmann::json& preparation_timing() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// One cell alone (its material and shape prepared for it): what run_study produces for that cell.
CellResult run_cell(const StudyPlan& plan, const StudyCell& cell, const Log& log = {});

// Writes a cell's featured images under out_dir (its images/ folder must exist).
void write_featured_images(const CellResult& cell, const std::filesystem::path& out_dir);

// ---- Aggregate: the run's files from its cells ----

// results.json's content from the cells' results in plan order: config, ground_truth, rows, images, summary
// (summarize), and with the area-light section area_summary and area_representative.
nlohmann::json aggregate_results(const StudyPlan& plan, const std::vector<CellResult>& cells);
// Writes results.json, results.csv, summary.md, area_summary.md (area-light section) and study.html.
void write_results(const nlohmann::json& results, const std::filesystem::path& out_dir);
// timing.json's content: CellRunner::preparation_timing, the cells' ground-truth and term times and rays
// summed, and the run's wall and CPU (all threads) seconds.
nlohmann::json aggregate_timing(const std::vector<CellResult>& cells, const nlohmann::json& preparation,
                                double wall_seconds, double cpu_seconds);

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

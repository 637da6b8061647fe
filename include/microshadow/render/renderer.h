// The reference CPU renderer: direct lighting with ray-traced shadows (Embree 3 for triangle meshes, analytic
// planes and spheres, a ray-marched height field for the ground truth), GGX (height-correlated Smith)
// specular plus Lambert diffuse, per-light micro-shadowing and bump-terminator terms. Tiles run in parallel
// (oneTBB); every pixel uses its own random streams, so the image is bit-identical whatever the thread count.
#pragma once

#include <microshadow/render/image.h>
#include <microshadow/render/scene.h>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace msh::render {

struct RenderStats {
  double seconds = 0;
  uint64_t camera_rays = 0, shadow_rays = 0, shaded_samples = 0;
};

// Shading inputs for one surface point and one light direction (world space), exposed for tests.
struct ShadePoint {
  Vec3f n_shading;  // normal-mapped shading normal
  Vec3f n_smooth;   // interpolated (unbumped) normal
  Vec3f n_geometric;
  Rgbf base_color;
  float roughness = 0.5f, metallic = 0.0f, visibility = 1.0f, specular = 1.0f;
  // The surface's tangent frame (x = +u, y = +v as the normal map, z = n_smooth) and the material's
  // per-texel micro-occlusion channels sampled at the hit (Material::directional; texel_channels = 0: none).
  Vec3f frame_u{1, 0, 0}, frame_v{0, 1, 0};
  std::array<float, 21> texel{};  // up to directional::kViewChannels
  int texel_channels = 0;
  std::array<float, 3> slope_covariance{};  // Material::slope_covariance
};

// GGX (height-correlated Smith G2, RTR4 9.31 + 9.41) + Lambert BRDF times cosine, with Schlick Fresnel
// F0 = lerp(metallic, 0.04·specular, base colour); diffuse weighted by (1 − F)(1 − metallic). Evaluated
// through the library's BRDF code (bsdf::microfacet_specular, bsdf::fresnel_schlick, bsdf::diffuse_lambert).
// N·V is clamped to 1e-4 (normal-mapped normals can face away from the viewer). wo, wi, n unit vectors.
Rgbf brdf_cos(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, float spec_scale = 1.0f,
              bool diffuse = true, bool specular = true);

// A render with its noise: the per-pixel mean and the standard error of that mean, per channel.
struct RenderResult {
  Image mean;
  // Standard error of each pixel's mean: sample standard deviation of the `batches` independent batch means
  // divided by sqrt(batches) (randomised quasi-Monte Carlo with independent scrambles, so the batch means are
  // i.i.d. unbiased estimates of the pixel integral). All zero when batches == 1.
  Image std_error;
  int batches = 1;
  int spp = 0;  // samples per pixel used
  RenderStats stats;
};

// Root-mean-square over pixels and channels of a standard-error image (the noise floor of a per-pixel RMSE:
// a measured RMSE² is the true RMSE² plus this squared, on average).
double rms_std_error(const Image& std_error);

// One window of a mosaic render (Renderer::render_windows_components): its camera, the light that replaces
// the scene's first light, its seed (Settings::seed's role) and its top-left pixel in the mosaic.
struct RenderWindow {
  Camera camera;
  Light light;
  uint32_t seed = 0;
  int x0 = 0, y0 = 0;
};

class Renderer {
 public:
  // Builds the acceleration structures and loads what the settings need (LUT). InputError when a mode cannot
  // run (e.g. a LUT method without a LUT file, ground truth without a height map).
  explicit Renderer(const Scene& scene);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // progress(fraction) is called from worker threads as tiles finish (may be empty).
  Image render(const std::function<void(double)>& progress = {}, RenderStats* stats = nullptr) const;
  // Mean and standard error (Settings::error_batches batches; the mean equals render() when it is 1).
  // InputError when spp is not a multiple of min(error_batches, spp).
  RenderResult render_with_error(const std::function<void(double)>& progress = {}) const;
  // Diffuse ([0]) and specular ([1]) in one pass: each bit-identical — mean and standard error — to
  // render_with_error() with Settings::component = Diffuse, respectively Specular (the same seed, spp and
  // batches, so the same samples), from one set of camera rays, shadow rays and term evaluations shared by
  // both (Settings::component is not read). Both elements carry the pass's stats (rays traced once).
  // InputError as render_with_error.
  std::array<RenderResult, 2> render_components_with_error(
      const std::function<void(double)>& progress = {}) const;
  // Several windows of Settings::width × height pixels each into one mosaic of mosaic_width × mosaic_height
  // (pixels no window covers stay 0), all windows' pixels in one parallel loop (the study's views at k <= 8
  // are 16 × 16 windows of 4 × 4 pixels: rendered one after the other, each was one thread's work). Window
  // i's pixels are bit-identical to render_components_with_error() with the scene's camera, first light and
  // Settings::seed set to window i's; stats are summed over the windows. InputError as
  // render_components_with_error, when the scene has no light or when a window leaves the mosaic.
  std::array<RenderResult, 2> render_windows_components(const std::vector<RenderWindow>& windows,
                                                        int mosaic_width, int mosaic_height) const;
  // Supersampling to a stated noise floor: render_with_error at spp = settings.spp (rounded up to a multiple
  // of error_batches), doubling spp until rms_std_error(std_error) <= target or the next step would exceed
  // max_spp; returns the last render (its spp in RenderResult::spp, stats summed over every pass).
  // Deterministic: the stopping test is a serial reduction over the finished image. InputError when
  // error_batches < 2, target is not positive, or max_spp < the starting spp or > 2^20.
  RenderResult render_to_error(double target_rms_std_error, int max_spp,
                               const std::function<void(double)>& progress = {}) const;
  // One pixel (all its samples), for tests and benchmarks.
  Rgbf render_pixel(int x, int y, RenderStats* stats = nullptr) const;

 private:
  RenderResult render_batches(int spp, int batches, const std::function<void(double)>& progress) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace msh::render

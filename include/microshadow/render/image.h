// Linear RGB framebuffer, tone mapping, image I/O glue and image-difference metrics for the renderer.
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/grid.h>

#include <filesystem>
#include <vector>

namespace msh::render {

// Linear (scene-referred) Rec.709 RGB, row 0 at the top.
struct Image : Grid<Rgbf> {
  using Grid::Grid;
};

// sRGB OETF (IEC 61966-2-1) of a linear value in [0,1], and its inverse.
float srgb_encode(float linear);
float srgb_decode(float encoded);

// Tone mapping for display: c · 2^exposure, clamped to [0,1], sRGB-encoded. Deliberately a plain clamp (no
// filmic curve) so that side-by-side images with the same exposure compare pixel values directly.
Rgbf tonemap(const Rgbf& linear, float exposure);

// Linear EXR (half) and tone-mapped 8-bit sRGB PNG; both atomic (no partial file on failure).
void write_exr(const std::filesystem::path& path, const Image& img);
void write_png(const std::filesystem::path& path, const Image& img, float exposure);
// For images that are already display-encoded in [0,1] (e.g. difference_image): no tone mapping.
void write_png_display(const std::filesystem::path& path, const Image& img);
// Reads a linear EXR written by write_exr (or any RGB(A) EXR).
Image read_exr(const std::filesystem::path& path);

// Root-mean-square error over all pixels and channels of linear RGB.
double rmse(const Image& a, const Image& b);
// Mean SSIM (Wang et al. 2004, 11×11 Gaussian window σ = 1.5, K1 = 0.01, K2 = 0.03, L = 1) of the luminance
// of the tone-mapped (display) images; 1 = identical. Both images use the same exposure.
double ssim(const Image& a, const Image& b, float exposure);
// False-colour difference |lum(a) − lum(b)| of the tone-mapped images, scaled by `gain`: blue = a darker than
// b, red = a brighter. Returned as a display (already tone-mapped) image.
Image difference_image(const Image& a, const Image& b, float exposure, float gain = 4.0f);
// Box-downsamples by an integer factor (used to compare at a coarser, texel-averaged scale).
Image downsample(const Image& img, int factor);

}  // namespace msh::render

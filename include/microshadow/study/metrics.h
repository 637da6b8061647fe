// Image-comparison metrics of the multiscale study (docs/study.md): mean-radiance bias, RMSE after averaging
// over a footprint of pixels, per-pixel RMSE, each with the noise floor that the ground truth's own Monte
// Carlo error puts under it. Every metric works on luminance (Rec.709 Y of linear RGB) over a region mask. No
// I/O, no threads.
#pragma once

#include <microshadow/math/grid.h>
#include <microshadow/render/image.h>

#include <cstdint>
#include <vector>

namespace msh::study {

// A single-channel double image, row 0 at the top.
struct Plane : Grid<double> {
  using Grid::Grid;
};

// Pixels of a region: 1 = inside (a new mask is all inside). Same size as the images it applies to.
struct Mask : Grid<uint8_t> {
  Mask() = default;
  Mask(int w, int h, uint8_t fill = 1) : Grid(w, h, fill) {}
  std::size_t count() const;
};

// Rec.709 luminance of each pixel.
Plane luminance(const render::Image& img);
// Standard error of the luminance from per-channel standard errors: Σ w_c σ_c. Exact when the channel errors
// are fully correlated (one geometry, one set of rays: nearly so here), an upper bound otherwise.
Plane luminance_stderr(const render::Image& se);

// A measured value and the floor the reference's noise puts under it (see each function).
struct Measure {
  double value = 0, floor = 0;
};

// Mean of `img` over the mask, and its standard error from per-pixel standard errors `se` (independent
// pixels: sqrt(Σ σ²) / n). An empty mask gives {0, 0}.
Measure region_mean(const Plane& img, const Plane& se, const Mask& m);

// Mean-radiance ratio Σ a / Σ g over the mask (1 = the same mean radiance as the reference g). Floor = its
// standard error from the reference's per-pixel errors g_se, to first order: (Σ a / Σ g) · sqrt(Σ σ²) / Σ g.
// a is taken as exact. A reference summing to zero gives {NaN, NaN} (callers skip such regions).
Measure bias(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m);

// Per-pixel RMSE over the mask, sqrt(mean (a − g)²). Floor = sqrt(mean σ²): the RMSE that the reference's
// noise alone gives against the noiseless truth (E[rmse²] = true rmse² + floor² for an exact a).
Measure rmse(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m);

// Box average over non-overlapping b × b blocks (the last partial row/column of blocks is dropped); a block
// is kept only when every pixel of it is inside the mask. Returns the block means, their standard errors
// sqrt(Σ σ²) / b² and the mask of kept blocks. b < 1 throws InputError.
struct Blocks {
  Plane mean, se;
  Mask mask;  // blocks kept
};
Blocks block_average(const Plane& img, const Plane& se, const Mask& m, int b);

// RMSE after averaging both images over b × b footprints: rmse(block_average(a), block_average(g)), with the
// floor of the block means' errors. b = 1 is the per-pixel RMSE. A zero-mean difference inside every
// footprint gives 0. b < 1 throws InputError.
Measure rmse_footprint(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m, int b);

}  // namespace msh::study

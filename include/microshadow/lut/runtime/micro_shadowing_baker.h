// Baker for the micro-shadowing LUT (Zurita 2026, "Improving Direct Lighting Material Occlusion - Part 2";
// layouts in micro_shadowing_lut.h and docs/lut.md).
//
// Algorithm (docs/lut.md): for the Smith profile the term is a ratio of VNDF masses,
//   R(V) = P[min(n·m, m·l) > sqrt(1 − V)] / P[m·l > 0],   m ~ VNDF(v, α),
// so for one (α, N·V) the VNDF samples are drawn once (Owen-scrambled Sobol, shared by all rows), and for one
// (N·L, φ) a single pass that bins the key min(n·m, m·l) by the Visibility texel it crosses yields the whole
// Visibility row (a cumulative histogram). The mean over φ ∈ [0, π] (and the cos(hφ) coefficients of the
// azimuth-aware table) uses Gauss-Legendre nodes in φ, each with its own scrambled point set. The V = 0 and
// V = 1 columns and the early-out region 2V + N·L < 1 are written exactly. Rows are independent tasks
// (oneTBB), so the result is bit-identical for any thread count. The cone layout bins by the t coordinate of
// the key's cone instead (rows of constant N·L, so the same single pass per (N·L, φ) gives the whole t row).
#pragma once

#include <microshadow/io/texture.h>
#include <microshadow/lut/micro_shadowing_lut.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace msh::lut {

struct BakeOptions {
  LutLayout layout = LutLayout::Seed;
  int n_vis = 64, n_nl = 64,
      n_nv = 64;          // texels per axis (each ≥ 2; n_nv unused with two_d); cone: n_vis = t
  int n_rough = 16;       // cone layout: roughness slabs (≥ 2)
  ConeLayoutParams cone;  // cone layout: warps and roughness range
  std::vector<double> roughness = {0.1, 0.4, 0.7, 1.0};  // one channel each, strictly increasing, in [0, 1]
  bool two_d = false;                                    // the N·V = 1 slice only (depth 1)
  int harmonics = 0;  // 0: mean over φ; H ≥ 1: azimuth-aware table, also a_h for cos(hφ), h ≤ H
  // VNDF samples per φ node and (roughness, N·V) pair for roughness ≥ 0.55, rounded up to a power of 2; half
  // as many below 0.55 and a quarter below 0.25, where the QMC error is smaller (docs/lut.md).
  int samples = 16384;
  int phi_nodes = 16;                                  // Gauss-Legendre nodes in φ ∈ [0, π]
  uint32_t seed = 1;                                   // scrambling seed (any value; the default bake uses 1)
  int threads = 0;                                     // 0: oneTBB's default
  std::function<void(double fraction_done)> progress;  // called from worker threads, serialized
};

// The default table (what `bake micro-shadowing` writes without --layout): cone layout, 64 t × 48 N·L ×
// 16 N·V × 16 roughness slabs (1.5 MiB as R16F), 4096 samples per φ node; with harmonics > 0 (a_0..a_H in
// RGBA) 48 t × 40 N·L × 16 × 16 (3.75 MiB as RGBA16F). docs/lut.md. A default-constructed BakeOptions is the
// seed layout (64³ × 4 channels, 16384 samples), bit-identical to the bake before the cone layout.
BakeOptions default_bake_options(LutLayout layout = LutLayout::Cone, int harmonics = 0);

// Throws msh::InputError naming the first bad field.
void validate(const BakeOptions& o);

// The baked table: width n_vis, height n_nl, depth n_nv·(H + 1) (two_d: H + 1), channels = roughness.size().
io::Volume bake_micro_shadowing_lut(const BakeOptions& o);

// A view of `vol` as a table with the given roughness per channel and harmonic count (throws InputError when
// the shape is inconsistent: depth not divisible by H + 1, more than 4 channels, roughness count ≠ channels).
MicroShadowingLutView make_view(const io::Volume& vol, const std::vector<double>& roughness, int harmonics);

// The same for a cone-layout table (depth = n_nv · n_rough, channels = harmonics + 1 or more).
MicroShadowingLutView make_cone_view(const io::Volume& vol, int n_rough, int harmonics,
                                     const ConeLayoutParams& params);
// Throws msh::InputError when a cone-layout parameter is out of range.
void validate_cone(const ConeLayoutParams& p);

// Samples per φ node the baker uses for roughness r (the power of 2 ≥ o.samples, scaled as documented above).
int samples_for_roughness(const BakeOptions& o, double roughness);

// Gauss-Legendre nodes on [0, π] and weights normalized to sum to 1 (the φ rule of the baker).
void phi_rule(int n, std::vector<double>& phi, std::vector<double>& weight);

// The straightforward baker for one texel, as the shader loop of Zurita 2026b does it: `samples` independent random
// VNDF samples (PCG32), split over `phi_strata` jittered φ strata, ratio of cone to hemisphere counts per
// stratum, mean over strata. Kept to measure the speed-up of the binned baker at equal error (bench only).
double monte_carlo_texel(double alpha, double visibility, double n_dot_l, double n_dot_v, int samples,
                         int phi_strata, uint64_t seed);

}  // namespace msh::lut

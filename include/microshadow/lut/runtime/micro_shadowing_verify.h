// As-used accuracy of any approximation of the generic VNDF micro-shadowing term (Zurita 2026, "Improving
// Direct Lighting Material Occlusion - Part 2"), isotropic Smith-GGX: a table through its sampler, an ALU
// fit, or an older closed-form term, measured at continuous random inputs over the whole domain against the
// exact term. docs/lut.md ("Verify") describes the measure and gives the figures.
//
// Inputs: N points of a 5D Owen-scrambled Sobol sequence (Burley 2020; Joe & Kuo 2008 directions), for seed s
//   V = u0 ∈ [0, 1), N·L = 1 − u1 ∈ (0, 1], N·V = 1 − u2 ∈ (0, 1], roughness = r_min + (r_max − r_min)·u3,
//   relative azimuth φ = π·u4 (the callable gets cos φ),
// rounded to float (what a shader holds); the reference is computed at the rounded values. The early-out
// region 2V + N·L < 1 (where the exact term is 0) is part of the domain and is counted.
// Reference, independent of any table or fit: the exact term (occlusion/micro_shadowing.h, closed-form
// denominator + adaptive Gauss-Kronrod; measured error < 1e-6), either its mean over φ ∈ [0, π] (what a
// plain table stores) or its value at the input's φ. Roughness r is the perceptual one, α = r².
// Threads (oneTBB) split the inputs; every input is computed on its own, so results are bit-identical for any
// thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace msh::lut {

enum class VerifyReference {
  AzimuthMean,  // mean over φ ∈ [0, π] of the exact term (the plain table's target)
  Azimuth,      // the exact term at the input's relative azimuth φ
};

// "mean" | "azimuth"; throws msh::InputError otherwise.
VerifyReference verify_reference_from_name(const std::string& name);
const char* verify_reference_name(VerifyReference r);

struct VerifyOptions {
  int samples = 10000;  // N ∈ [1, 10⁷]
  uint32_t seed = 1;    // any value (each gives an independent scrambling)
  VerifyReference against = VerifyReference::AzimuthMean;
  double roughness_min = 0.1, roughness_max = 1.0;  // 0 ≤ min ≤ max ≤ 1
  int threads = 0;                                  // 0: oneTBB's default
  int worst = 10;                                   // how many worst inputs to keep
  // Band edges, strictly increasing (or two equal edges: one band [e, e]): band i is [e_i, e_{i+1}), the last
  // one closed.
  std::vector<double> roughness_bands = {0.1, 0.25, 0.55, 1.0};
  std::vector<double> n_dot_v_bands = {0.0, 0.25, 0.5, 0.75, 1.0};
};

// Throws msh::InputError naming the first bad field.
void validate(const VerifyOptions& o);

// One input and its exact reference value.
struct VerifyInput {
  float visibility, n_dot_l, n_dot_v, roughness, cos_phi;
  double exact;
};

// Statistics of e = approx − exact over a set of inputs, absolute units (×255 for 8-bit units). p99 is the
// nearest-rank 99th percentile of |e|. A non-finite approximation counts with |e| = 1 (the term's range).
struct ErrorStats {
  std::size_t count = 0, nonfinite = 0;
  double rms = 0, p99 = 0, max_abs = 0, mean = 0;
};
ErrorStats error_stats(const std::vector<double>& errors);

struct VerifyBand {
  double lo, hi;
  ErrorStats stats;
};

struct VerifyWorst {
  std::size_t index;  // into the inputs
  VerifyInput input;
  double approx, error;
};

struct VerifyResult {
  ErrorStats all;
  ErrorStats early_out, rest;  // 2V + N·L < 1 (in float, as the samplers test it), and the other inputs
  std::vector<VerifyBand> by_roughness, by_n_dot_v;
  std::vector<VerifyWorst> worst;  // largest |e| first (ties: lower index first)
  std::vector<double> approx;      // the approximation at every input, in input order
};

// The approximation under test: float(V, N·L, N·V, roughness, cos φ). Called concurrently from several
// threads; must not keep state between calls.
using MicroShadowingApprox =
    std::function<float(float visibility, float n_dot_l, float n_dot_v, float roughness, float cos_phi)>;

// The N inputs and their exact values (the expensive part: ≈ 0.4 ms CPU per input against the azimuth mean,
// ≈ 0.03 ms against the azimuth). Compute once, measure several approximations with measure().
std::vector<VerifyInput> make_verify_inputs(const VerifyOptions& o);

// Error statistics of `f` on `inputs` (bands, worst inputs from `o`).
VerifyResult measure(const std::vector<VerifyInput>& inputs, const MicroShadowingApprox& f,
                     const VerifyOptions& o);

// make_verify_inputs + measure.
VerifyResult verify_micro_shadowing(const MicroShadowingApprox& f, const VerifyOptions& o);

// The exact reference at one input (what make_verify_inputs stores), double precision.
double verify_reference_value(VerifyReference against, double visibility, double n_dot_l, double n_dot_v,
                              double roughness, double cos_phi);

}  // namespace msh::lut

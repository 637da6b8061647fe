// Bakers for the BRDF tables (src/bsdf/tables.cpp): GGX directional albedo E(μ, r) and its averages Ē(r),
// the split-sum DFG table (Karis 2013) and its multiscatter variant (Filament), and the generator of the
// shipped C++ header tables_data.h. Deterministic: each texel is a pure function of its coordinates and the
// sample count (fixed-seed QMC), so the output is identical whatever the thread count (oneTBB).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace msh::bsdf {

// Texel (i, j) holds μ = i/(n_mu − 1), r = j/(n_r − 1); arrays are [j * n_mu + i] (μ fastest).
struct GgxAlbedoTable {
  int n_mu = 0, n_r = 0;
  uint32_t samples = 0;
  std::vector<double> e;        // E(μ, r) = ∫ f_sF1 (n·l) dl, height-correlated GGX, F = 1
  std::vector<double> e_fc;     // E_Fc(μ, r) = ∫ (1 − v·h)⁵ f_sF1 (n·l) dl
  std::vector<double> e_avg;    // Ē(r) = 2 ∫ E(μ) μ dμ            [j]
  std::vector<double> efc_avg;  // Ē_Fc(r) = 2 ∫ E_Fc(μ) μ dμ      [j]
};

// Bakes n_mu × n_r texels with `samples` QMC samples each; the averages use a 32-node Gauss-Legendre rule in
// μ (E evaluated directly at the nodes, not interpolated). Threads: oneTBB; result independent of their
// number.
GgxAlbedoTable bake_ggx_albedo(int n_mu, int n_r, uint32_t samples, int avg_nodes = 32);

// The C++ source of include/microshadow/bsdf/tables_data.h for a baked table (n_mu == n_r required).
std::string shipped_tables_header(const GgxAlbedoTable& t);

// Shipped-table parameters: 32×32, 2^16 samples per texel.
inline constexpr int kShippedTableSize = 32;
inline constexpr uint32_t kShippedTableSamples = 1u << 16;

}  // namespace msh::bsdf

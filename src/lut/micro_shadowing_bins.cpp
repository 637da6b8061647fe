// SIMD kernel of the LUT baker's row pass (Highway, dynamic dispatch): the Visibility bin of each VNDF
// sample. Scalar definition (also the tail): key = min(n·m, m·l), m·l = sl·p + zl·n·m;
//   bin = key > 0 ? min(int((n_vis − 1)(1 − key²)) + 1, n_vis − 1) : n_vis.
#undef HWY_TARGET_INCLUDE
// Re-included once per SIMD target; found through the project include directory (include/).
#define HWY_TARGET_INCLUDE "../src/lut/micro_shadowing_bins.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace msh::lut::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void ComputeBins(const float* HWY_RESTRICT mz, const float* HWY_RESTRICT p, std::size_t n, float zl, float sl,
                 int32_t n_vis, int32_t* HWY_RESTRICT bins) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const std::size_t lanes = hn::Lanes(df);
  const auto vzl = hn::Set(df, zl), vsl = hn::Set(df, sl), one = hn::Set(df, 1.0f);
  const auto scale = hn::Set(df, float(n_vis - 1)), zero = hn::Zero(df);
  const auto ione = hn::Set(di, 1), ilast = hn::Set(di, n_vis - 1), idump = hn::Set(di, n_vis);
  std::size_t j = 0;
  for (; j + lanes <= n; j += lanes) {
    const auto z = hn::LoadU(df, mz + j);
    // No fused multiply-add: every target (and the scalar tail) rounds the same way, so bins never depend
    // on the CPU the baker runs on.
    const auto ml = hn::Add(hn::Mul(vsl, hn::LoadU(df, p + j)), hn::Mul(vzl, z));
    const auto key = hn::Min(z, ml);
    const auto t = hn::Mul(scale, hn::Sub(one, hn::Mul(key, key)));
    const auto bin = hn::Min(hn::Add(hn::ConvertTo(di, t), ione), ilast);
    const auto lit = hn::RebindMask(di, hn::Gt(key, zero));
    hn::StoreU(hn::IfThenElse(lit, bin, idump), di, bins + j);
  }
  for (; j < n; ++j) {
    const float key = std::min(mz[j], sl * p[j] + zl * mz[j]);
    const int32_t bin = std::min(int32_t(float(n_vis - 1) * (1.0f - key * key)) + 1, n_vis - 1);
    bins[j] = key > 0.0f ? bin : n_vis;
  }
}

// Cone layout: the bin is the first t texel whose cone the key's cone contains, t(key) from
// micro_shadowing_lut.h cone_t with cos θ = key (θ may exceed π/2: key < 0): d = sqrt(1 − key²)·zl − key·sl,
// u = d/(a + |d|), t = (u − ulo)·inv_range; bin = t < 1 ? clamp(int((n − 1) t) + 1, 1, n − 1) : n. Returns
// the number of samples with key > 0 (the hemisphere count, the ratio's denominator).
int64_t ComputeBinsCone(const float* HWY_RESTRICT mz, const float* HWY_RESTRICT p, std::size_t n, float zl,
                        float sl, float a, float ulo, float inv_range, int32_t n_vis,
                        int32_t* HWY_RESTRICT bins) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const std::size_t lanes = hn::Lanes(df);
  const auto vzl = hn::Set(df, zl), vsl = hn::Set(df, sl), one = hn::Set(df, 1.0f), zero = hn::Zero(df);
  const auto va = hn::Set(df, a), vulo = hn::Set(df, ulo), vinv = hn::Set(df, inv_range);
  const auto scale = hn::Set(df, float(n_vis - 1));
  const auto ione = hn::Set(di, 1), ilast = hn::Set(di, n_vis - 1), idump = hn::Set(di, n_vis);
  int64_t lit = 0;
  std::size_t j = 0;
  for (; j + lanes <= n; j += lanes) {
    const auto z = hn::LoadU(df, mz + j);
    const auto ml = hn::Add(hn::Mul(vsl, hn::LoadU(df, p + j)), hn::Mul(vzl, z));  // no FMA (see above)
    const auto key = hn::Min(z, ml);
    const auto sv = hn::Sqrt(hn::Max(zero, hn::Sub(one, hn::Mul(key, key))));
    const auto d = hn::Sub(hn::Mul(sv, vzl), hn::Mul(key, vsl));
    const auto u = hn::Div(d, hn::Add(va, hn::Abs(d)));
    const auto tn = hn::Mul(hn::Sub(u, vulo), vinv);
    const auto t = hn::Mul(scale, tn);
    const auto bin = hn::Max(hn::Min(hn::Add(hn::ConvertTo(di, t), ione), ilast), ione);
    const auto inside = hn::RebindMask(di, hn::Lt(tn, one));
    hn::StoreU(hn::IfThenElse(inside, bin, idump), di, bins + j);
    lit += int64_t(hn::CountTrue(df, hn::Gt(key, zero)));
  }
  for (; j < n; ++j) {
    const float key = std::min(mz[j], sl * p[j] + zl * mz[j]);
    const float sv = std::sqrt(std::max(0.0f, 1.0f - key * key));
    const float d = sv * zl - key * sl;
    const float u = d / (a + std::abs(d));
    const float tn = (u - ulo) * inv_range;
    const int32_t bin = std::max(std::min(int32_t(float(n_vis - 1) * tn) + 1, n_vis - 1), int32_t(1));
    bins[j] = tn < 1.0f ? bin : n_vis;
    lit += key > 0.0f;
  }
  return lit;
}

}  // namespace msh::lut::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace msh::lut {
HWY_EXPORT(ComputeBins);
HWY_EXPORT(ComputeBinsCone);

// Declared in micro_shadowing_baker.cpp.
void compute_bins(const float* mz, const float* p, std::size_t n, float zl, float sl, int32_t n_vis,
                  int32_t* bins) {
  HWY_DYNAMIC_DISPATCH(ComputeBins)(mz, p, n, zl, sl, n_vis, bins);
}
int64_t compute_bins_cone(const float* mz, const float* p, std::size_t n, float zl, float sl, float a,
                          float ulo, float inv_range, int32_t n_vis, int32_t* bins) {
  return HWY_DYNAMIC_DISPATCH(ComputeBinsCone)(mz, p, n, zl, sl, a, ulo, inv_range, n_vis, bins);
}
}  // namespace msh::lut
#endif

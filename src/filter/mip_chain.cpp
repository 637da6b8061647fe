#include <fmt/format.h>
#include <microshadow/filter/lean.h>
#include <microshadow/filter/runtime/mip_chain.h>
#include <microshadow/filter/toksvig.h>
#include <microshadow/filter/variance_mapping.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace msh::filter {

namespace {
constexpr Named<FilterMethod> kFilterMethods[] = {
    {FilterMethod::Toksvig, "toksvig"}, {FilterMethod::Variance, "variance"}, {FilterMethod::Lean, "lean"}};
}  // namespace

FilterMethod filter_method_from_name(const std::string& name) {
  return value_of<FilterMethod>(kFilterMethods, name, "filter method");
}

std::string filter_method_name(FilterMethod m) { return name_of<FilterMethod>(kFilterMethods, m); }

namespace {

// Sums over a footprint, in double: unit normals (Toksvig), LEAN slope moments (with the base roughness on
// the diagonal) and α² (the base roughness for Toksvig).
struct Sums {
  double w = 0, nx = 0, ny = 0, nz = 0, a2 = 0;
  LeanMoments<double> lean;
  void add(const Sums& o) {
    w += o.w, nx += o.nx, ny += o.ny, nz += o.nz, a2 += o.a2;
    lean += o.lean;
  }
};

void finish_level(const std::vector<Sums>& s, MipLevel& lv, FilterMethod method, double k) {
  const size_t n = size_t(lv.width) * size_t(lv.height);
  lv.channels = method == FilterMethod::Lean ? 2 : 1;
  lv.roughness.assign(n * size_t(lv.channels), 0.0f);
  lv.normal.assign(n * 3, 0.0f);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Sums& t = s[i];
      const double inv = 1.0 / t.w;
      const Vec3d mean(t.nx * inv, t.ny * inv, t.nz * inv);
      const Vec3d nn = normalize(mean);
      lv.normal[3 * i + 0] = float(nn.x), lv.normal[3 * i + 1] = float(nn.y),
                        lv.normal[3 * i + 2] = float(nn.z);
      const SlopeCovariance<double> cov = lean_covariance(t.lean.normalized());
      switch (method) {
        case FilterMethod::Toksvig: {
          const double alpha = std::sqrt(t.a2 * inv);
          lv.roughness[i] = float(std::sqrt(toksvig_ggx_alpha(alpha, length(mean))));
          break;
        }
        case FilterMethod::Variance:
          // Mean per-axis slope variance (base roughness included through the LEAN diagonal).
          lv.roughness[i] = float(slope_variance_to_roughness(0.5 * (cov.xx + cov.yy), k));
          break;
        case FilterMethod::Lean: {
          lv.roughness[2 * i + 0] = float(slope_variance_to_roughness(cov.xx, k));
          lv.roughness[2 * i + 1] = float(slope_variance_to_roughness(cov.yy, k));
          break;
        }
      }
    }
  });
  // Normal-only variance (base roughness removed), for reports: mean over texels, fixed order.
  double acc = 0;
  for (size_t i = 0; i < n; ++i) {
    const SlopeCovariance<double> cov = lean_covariance(s[i].lean.normalized());
    acc += 0.5 * (cov.xx + cov.yy) - 0.5 * k * s[i].a2 / s[i].w;  // minus the base k α²/2
  }
  lv.mean_normal_variance = std::max(0.0, acc / double(n));
}

}  // namespace

std::vector<MipLevel> build_roughness_mips(int width, int height, const std::vector<Vec3f>& normals,
                                           const std::vector<float>& roughness, FilterMethod method,
                                           int max_levels, double ggx_variance_scale) {
  const double k = ggx_variance_scale;
  if (!(k > 0) || !std::isfinite(k))
    throw InputError(fmt::format("filter: GGX variance scale must be positive, got {}", k));
  if (width <= 0 || height <= 0) throw InputError("filter: empty normal map");
  const size_t n0 = size_t(width) * size_t(height);
  if (normals.size() != n0)
    throw InputError(fmt::format("filter: normal map has {} texels, expected {}", normals.size(), n0));
  if (roughness.size() != n0 && roughness.size() != 1)
    throw InputError(
        fmt::format("filter: roughness map has {} texels, expected {} (the normal map's size) or 1",
                    roughness.size(), n0));

  std::vector<Sums> cur(n0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n0, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Vec3d nd(normals[i]);
      if (!is_finite(nd)) nd = Vec3d(0, 0, 1);
      nd.z = std::max(nd.z, 1e-4);
      nd = normalize(nd);
      const double rr = saturate(double(roughness.size() == 1 ? roughness[0] : roughness[i]));
      const double a = rr * rr;
      Sums s;
      s.w = 1, s.nx = nd.x, s.ny = nd.y, s.nz = nd.z, s.a2 = a * a;
      s.lean = LeanMoments<double>::from_normal(nd, a, a, k);
      cur[i] = s;
    }
  });

  std::vector<MipLevel> out;
  int w = width, h = height;
  for (int level = 0;; ++level) {
    MipLevel lv;
    lv.width = w, lv.height = h;
    finish_level(cur, lv, method, k);
    out.push_back(std::move(lv));
    if ((w == 1 && h == 1) || (max_levels > 0 && int(out.size()) >= max_levels)) break;
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    std::vector<Sums> next(size_t(nw) * size_t(nh));
    tbb::parallel_for(tbb::blocked_range<int>(0, nh), [&](const tbb::blocked_range<int>& r) {
      for (int y = r.begin(); y != r.end(); ++y) {
        const int y0 = int(int64_t(y) * h / nh), y1 = int(int64_t(y + 1) * h / nh);
        for (int x = 0; x < nw; ++x) {
          const int x0 = int(int64_t(x) * w / nw), x1 = int(int64_t(x + 1) * w / nw);
          Sums s;
          for (int yy = y0; yy < y1; ++yy)
            for (int xx = x0; xx < x1; ++xx) s.add(cur[size_t(yy) * size_t(w) + size_t(xx)]);
          next[size_t(y) * size_t(nw) + size_t(x)] = s;
        }
      }
    });
    cur.swap(next);
    w = nw, h = nh;
  }
  return out;
}

}  // namespace msh::filter

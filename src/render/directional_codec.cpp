// Compact forms of the directional channels (render/directional_codec.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace msh::render {

namespace dir = msh::directional;

namespace {

// φ(l, v): what the C channels are dotted with at run time (directional_transport for C = 9,
// directional_view_transport for C = 21, before the final max(0, ·)).
void transport_features(Vec3d l, Vec3d v, int C, double* phi) {
  double b[dir::kPoly2Terms];
  dir::poly2_basis(l, b);
  for (int i = 0; i < dir::kPoly2Terms; ++i) phi[i] = b[i];
  if (C == dir::kDirectionalChannels) return;
  const double vz = std::max(v.z, dir::kMinViewZ);
  for (int i = 0; i < dir::kSlopeTerms; ++i) {
    phi[dir::kPoly2Terms + i] = b[i] * v.x / vz;
    phi[dir::kPoly2Terms + dir::kSlopeTerms + i] = b[i] * v.y / vz;
  }
}

// Eigen-decomposition of a symmetric n × n matrix (row-major) by cyclic Jacobi rotations (Golub & Van Loan
// 2013, "Matrix Computations" §8.5): eigenvalues descending, eigenvectors as the columns of V, each with its
// largest-magnitude component positive (a deterministic sign).
void symmetric_eigen(std::vector<double> A, int n, std::vector<double>& values, std::vector<double>& V) {
  V.assign(std::size_t(n) * n, 0.0);
  for (int i = 0; i < n; ++i) V[std::size_t(i) * n + i] = 1;
  auto a = [&](int i, int j) -> double& { return A[std::size_t(i) * n + j]; };
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0, diag = 0;
    for (int i = 0; i < n; ++i) {
      diag += a(i, i) * a(i, i);
      for (int j = i + 1; j < n; ++j) off += a(i, j) * a(i, j);
    }
    if (off <= 1e-30 * diag || off == 0) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        if (a(p, q) == 0) continue;
        const double theta = (a(q, q) - a(p, p)) / (2 * a(p, q));
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < n; ++k) {  // A ← A J (columns p, q)
          const double akp = a(k, p), akq = a(k, q);
          a(k, p) = c * akp - s * akq, a(k, q) = s * akp + c * akq;
        }
        for (int k = 0; k < n; ++k) {  // A ← Jᵀ A (rows p, q)
          const double apk = a(p, k), aqk = a(q, k);
          a(p, k) = c * apk - s * aqk, a(q, k) = s * apk + c * aqk;
        }
        for (int k = 0; k < n; ++k) {
          double& vkp = V[std::size_t(k) * n + p];
          double& vkq = V[std::size_t(k) * n + q];
          const double x = vkp, y = vkq;
          vkp = c * x - s * y, vkq = s * x + c * y;
        }
      }
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return a(x, x) > a(y, y); });
  std::vector<double> W(std::size_t(n) * n);
  values.resize(std::size_t(n));
  for (int c = 0; c < n; ++c) {
    const int o = order[std::size_t(c)];
    values[std::size_t(c)] = a(o, o);
    int big = 0;
    for (int k = 1; k < n; ++k)
      if (std::abs(V[std::size_t(k) * n + o]) > std::abs(V[std::size_t(big) * n + o])) big = k;
    const double sgn = V[std::size_t(big) * n + o] < 0 ? -1 : 1;
    for (int k = 0; k < n; ++k) W[std::size_t(k) * n + c] = sgn * V[std::size_t(k) * n + o];
  }
  V = std::move(W);
}

// Lower-triangular L with M = L Lᵀ (M symmetric positive definite, row-major); InputError if it is not.
std::vector<double> cholesky(const std::vector<double>& M, int n) {
  std::vector<double> L(std::size_t(n) * n, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      double s = M[std::size_t(i) * n + j];
      for (int k = 0; k < j; ++k) s -= L[std::size_t(i) * n + k] * L[std::size_t(j) * n + k];
      if (i == j) {
        if (!(s > 0)) throw InputError("directional codec: the transport metric is not positive definite");
        L[std::size_t(i) * n + i] = std::sqrt(s);
      } else {
        L[std::size_t(i) * n + j] = s / L[std::size_t(j) * n + j];
      }
    }
  return L;
}

void check_channels(int C, const char* what) {
  if (C != dir::kDirectionalChannels && C != dir::kViewChannels)
    throw InputError(fmt::format("{}: the directional channels are {} or {}, got {}", what,
                                 dir::kDirectionalChannels, dir::kViewChannels, C));
}

}  // namespace

DirectionalCodec parse_directional_form(const std::string& form, int channels) {
  check_channels(channels, "directional form");
  DirectionalCodec c;
  c.form = form, c.channels = channels;
  const auto bad = [&] {
    return InputError(fmt::format(
        "directional form must be pca<K>, pca<K>x16 or pca<K>f with 1 <= K <= {}, got '{}'", channels, form));
  };
  if (form.rfind("pca", 0) != 0) throw bad();
  std::size_t i = 3, j = 3;
  while (j < form.size() && j - i < 3 && std::isdigit(static_cast<unsigned char>(form[j]))) ++j;
  if (j == i) throw bad();
  c.coefficients = std::stoi(form.substr(i, j - i));
  const std::string tail = form.substr(j);
  if (tail.empty())
    c.bits = 8;
  else if (tail == "x16")
    c.bits = 16;
  else if (tail == "f")
    c.bits = 0;
  else
    throw bad();
  if (c.coefficients < 1 || c.coefficients > channels) throw bad();
  return c;
}

std::vector<double> directional_transport_metric(const std::vector<float>& mean) {
  const int C = int(mean.size());
  check_channels(C, "directional_transport_metric");
  std::vector<Vec3d> views{{0, 0, 1}};
  if (C == dir::kViewChannels)
    for (double zen : {30.0, 60.0})
      for (int a = 0; a < 8; ++a) {
        const double t = zen * kPi<double> / 180, p = 2 * kPi<double> * (a + 0.5) / 8;
        views.push_back({std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)});
      }
  std::vector<double> M(std::size_t(C) * C, 0.0), phi(static_cast<std::size_t>(C));
  for (int e = 5; e <= 75; e += 5)
    for (int a = 0; a < 24; ++a) {
      const double el = e * kPi<double> / 180, p = 2 * kPi<double> * (a + 0.5) / 24;
      const Vec3d l{std::cos(el) * std::cos(p), std::cos(el) * std::sin(p), std::sin(el)};
      for (const Vec3d& v : views) {
        transport_features(l, v, C, phi.data());
        double t = 0;
        for (int i = 0; i < C; ++i) t += phi[std::size_t(i)] * mean[std::size_t(i)];
        const double w = 1 / std::pow(std::max(t, 0.01), 2);
        for (int i = 0; i < C; ++i)
          for (int j = 0; j < C; ++j)
            M[std::size_t(i) * C + j] += w * phi[std::size_t(i)] * phi[std::size_t(j)];
      }
    }
  return M;
}

DirectionalCodec fit_directional_codec(const Texture& fine, const std::string& form) {
  const int C = fine.channels(), w = fine.width(), h = fine.height();
  DirectionalCodec codec = parse_directional_form(form, C);
  if (fine.empty()) throw InputError("fit_directional_codec: no channels");
  const int K = codec.coefficients;
  // Mean and covariance in double, per block of rows, summed in block order (deterministic).
  const int nb = std::min(h, 64);
  std::vector<std::vector<double>> s1(std::size_t(nb), std::vector<double>(std::size_t(C), 0.0));
  std::vector<std::vector<double>> s2(std::size_t(nb), std::vector<double>(std::size_t(C) * C, 0.0));
  tbb::parallel_for(0, nb, [&](int b) {
    std::vector<double>& m1 = s1[std::size_t(b)];
    std::vector<double>& m2 = s2[std::size_t(b)];
    for (int y = int(std::int64_t(h) * b / nb); y < int(std::int64_t(h) * (b + 1) / nb); ++y)
      for (int x = 0; x < w; ++x)
        for (int i = 0; i < C; ++i) {
          const double ci = fine.at(x, y, i);
          if (!std::isfinite(ci)) throw InputError("fit_directional_codec: a channel is not finite");
          m1[std::size_t(i)] += ci;
          for (int j = 0; j <= i; ++j) m2[std::size_t(i) * C + j] += ci * fine.at(x, y, j);
        }
  });
  const double n = double(w) * double(h);
  std::vector<double> mean(std::size_t(C), 0.0), cov(std::size_t(C) * C, 0.0);
  for (int b = 0; b < nb; ++b)
    for (int i = 0; i < C; ++i) {
      mean[std::size_t(i)] += s1[std::size_t(b)][std::size_t(i)];
      for (int j = 0; j <= i; ++j) cov[std::size_t(i) * C + j] += s2[std::size_t(b)][std::size_t(i) * C + j];
    }
  for (double& m : mean) m /= n;
  for (int i = 0; i < C; ++i)
    for (int j = 0; j <= i; ++j) {
      const double v = cov[std::size_t(i) * C + j] / n - mean[std::size_t(i)] * mean[std::size_t(j)];
      cov[std::size_t(i) * C + j] = cov[std::size_t(j) * C + i] = v;
    }
  codec.mean.assign(mean.begin(), mean.end());
  // Σ_d = Lᵀ Σ L, its leading eigenvectors U; E = Uᵀ Lᵀ, B = L⁻ᵀ U.
  const std::vector<double> L = cholesky(directional_transport_metric(codec.mean), C);
  auto l = [&](int i, int j) { return L[std::size_t(i) * C + j]; };
  std::vector<double> SL(std::size_t(C) * C, 0.0), Sd(std::size_t(C) * C, 0.0);
  for (int i = 0; i < C; ++i)
    for (int j = 0; j < C; ++j)
      for (int k = j; k < C; ++k) SL[std::size_t(i) * C + j] += cov[std::size_t(i) * C + k] * l(k, j);
  for (int i = 0; i < C; ++i)
    for (int j = 0; j < C; ++j)
      for (int k = i; k < C; ++k) Sd[std::size_t(i) * C + j] += l(k, i) * SL[std::size_t(k) * C + j];
  std::vector<double> values, U;
  symmetric_eigen(Sd, C, values, U);
  const double total = std::accumulate(values.begin(), values.end(), 0.0,
                                       [](double s, double v) { return s + std::max(v, 0.0); });
  codec.encode.assign(std::size_t(K) * C, 0.0f);
  codec.basis.assign(std::size_t(C) * K, 0.0f);
  for (int k = 0; k < K; ++k) {
    codec.explained.push_back(total > 0 ? std::max(values[std::size_t(k)], 0.0) / total : 0.0);
    for (int i = 0; i < C; ++i) {  // E[k][i] = Σ_j U[j][k] Lᵀ[j][i], Lᵀ[j][i] = L[i][j], nonzero for j ≤ i
      double e = 0;
      for (int j = 0; j <= i; ++j) e += U[std::size_t(j) * C + k] * l(i, j);
      codec.encode[std::size_t(k) * C + i] = float(e);
    }
    // B[:, k] solves Lᵀ x = U[:, k] (upper triangular, back substitution).
    std::vector<double> x(static_cast<std::size_t>(C));
    for (int i = C - 1; i >= 0; --i) {
      double s = U[std::size_t(i) * C + k];
      for (int j = i + 1; j < C; ++j) s -= l(j, i) * x[std::size_t(j)];
      x[std::size_t(i)] = s / l(i, i);
    }
    for (int i = 0; i < C; ++i) codec.basis[std::size_t(i) * K + k] = float(x[std::size_t(i)]);
  }
  // The coefficients' range over the fine texels (a mip level's means stay inside it).
  const ChannelRanges r = channel_ranges(encode_directional(fine, codec));
  codec.lo = r.lo, codec.hi = r.hi;
  return codec;
}

std::vector<float> DirectionalCodec::folded_mean() const {
  std::vector<float> m(std::size_t(channels), 0.0f);
  for (int i = 0; i < channels; ++i) {
    double s = mean[std::size_t(i)];
    for (int k = 0; k < coefficients; ++k)
      s += double(basis[std::size_t(i) * coefficients + k]) * lo[std::size_t(k)];
    m[std::size_t(i)] = float(s);
  }
  return m;
}

std::vector<float> DirectionalCodec::folded_basis() const {
  std::vector<float> b(basis.size());
  for (int i = 0; i < channels; ++i)
    for (int k = 0; k < coefficients; ++k)
      b[std::size_t(i) * coefficients + k] = float(double(basis[std::size_t(i) * coefficients + k]) *
                                                   (double(hi[std::size_t(k)]) - lo[std::size_t(k)]));
  return b;
}

namespace {
std::vector<std::vector<float>> rows_of(const std::vector<float>& m, int rows, int cols) {
  std::vector<std::vector<float>> r;
  for (int i = 0; i < rows; ++i)
    r.emplace_back(m.begin() + std::ptrdiff_t(i) * cols, m.begin() + std::ptrdiff_t(i + 1) * cols);
  return r;
}
}  // namespace

std::vector<std::vector<float>> DirectionalCodec::basis_rows() const {
  return rows_of(basis, channels, coefficients);
}
std::vector<std::vector<float>> DirectionalCodec::folded_basis_rows() const {
  return rows_of(folded_basis(), channels, coefficients);
}

namespace {
// The texture of `out_channels` channels whose texel (x, y) channel k is f(x, y, k), rows in parallel; `in`
// must have `in_channels` channels (`what`: the caller, for the error).
template <class F>
Texture map_texels(const char* what, const Texture& in, int in_channels, int out_channels, const F& f) {
  if (in.channels() != in_channels)
    throw InputError(fmt::format("{}: {} channels, the code takes {}", what, in.channels(), in_channels));
  Texture out(in.width(), in.height(), out_channels);
  tbb::parallel_for(0, in.height(), [&](int y) {
    for (int x = 0; x < in.width(); ++x)
      for (int k = 0; k < out_channels; ++k) out.at(x, y, k) = f(x, y, k);
  });
  return out;
}
}  // namespace

Texture encode_directional(const Texture& channels, const DirectionalCodec& codec) {
  const int C = codec.channels;
  return map_texels("encode_directional", channels, C, codec.coefficients, [&](int x, int y, int k) {
    double s = 0;
    for (int i = 0; i < C; ++i)
      s += double(codec.encode[std::size_t(k) * C + i]) *
           (double(channels.at(x, y, i)) - codec.mean[std::size_t(i)]);
    return float(s);
  });
}

Texture decode_directional(const Texture& coefficients, const DirectionalCodec& codec) {
  const int K = codec.coefficients;
  return map_texels("decode_directional", coefficients, K, codec.channels, [&](int x, int y, int i) {
    double s = codec.mean[std::size_t(i)];
    for (int k = 0; k < K; ++k) s += double(codec.basis[std::size_t(i) * K + k]) * coefficients.at(x, y, k);
    return float(s);
  });
}

void quantize_coefficients(Texture& a, const DirectionalCodec& codec) {
  if (codec.bits == 0) return;
  const float q = float((1 << codec.bits) - 1);
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      for (int k = 0; k < codec.coefficients; ++k) {
        const float lo = codec.lo[std::size_t(k)], hi = codec.hi[std::size_t(k)];
        const float u = std::clamp((a.at(x, y, k) - lo) / (hi - lo), 0.0f, 1.0f);
        a.at(x, y, k) = lo + (hi - lo) * (std::round(u * q) / q);
      }
}

Texture store_through_codec(const Texture& channels, const DirectionalCodec& codec) {
  Texture a = encode_directional(channels, codec);
  quantize_coefficients(a, codec);
  return decode_directional(a, codec);
}

}  // namespace msh::render

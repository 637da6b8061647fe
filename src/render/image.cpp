// Framebuffer I/O, tone mapping and image metrics (see render/image.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/math/vec.h>
#include <microshadow/render/image.h>

#include <algorithm>
#include <cmath>

namespace msh::render {

float srgb_encode(float x) {
  x = saturate(x);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}
float srgb_decode(float x) {
  x = saturate(x);
  return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
}

Rgbf tonemap(const Rgbf& c, float exposure) {
  const float k = std::exp2(exposure);
  return {srgb_encode(c.r * k), srgb_encode(c.g * k), srgb_encode(c.b * k)};
}

namespace {
io::Volume to_volume(const Image& img, bool display, float exposure) {
  io::Volume v(img.width, img.height, 1, 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      Rgbf c = img.at(x, y);
      if (display) c = tonemap(c, exposure);
      if (!is_finite(c)) c = Rgbf(0.0f);
      for (int k = 0; k < 3; ++k) v.at(x, y, 0, k) = c[k];
    }
  return v;
}
float lum_display(const Rgbf& c, float exposure) { return luminance(tonemap(c, exposure)); }
void require_same_size(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.width == 0)
    throw InputError(
        fmt::format("images differ in size ({}x{} vs {}x{})", a.width, a.height, b.width, b.height));
}
}  // namespace

void write_exr(const std::filesystem::path& path, const Image& img) {
  io::write_exr(path, to_volume(img, false, 0.0f), true);
}
void write_png(const std::filesystem::path& path, const Image& img, float exposure) {
  io::write_png(path, to_volume(img, true, exposure), 8);
}
void write_png_display(const std::filesystem::path& path, const Image& img) {
  io::write_png(path, to_volume(img, false, 0.0f), 8);
}

Image read_exr(const std::filesystem::path& path) {
  const io::Volume v = io::read_image(path);
  if (v.channels < 3)
    throw InputError(fmt::format("{}: expected an RGB image, got {} channels", path.string(), v.channels));
  Image img(v.width, v.height);
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) img.at(x, y) = {v.at(x, y, 0, 0), v.at(x, y, 0, 1), v.at(x, y, 0, 2)};
  return img;
}

double rmse(const Image& a, const Image& b) {
  require_same_size(a, b);
  double s = 0;
  for (std::size_t i = 0; i < a.px.size(); ++i)
    for (int k = 0; k < 3; ++k) s += sqr(double(a.px[i][k]) - double(b.px[i][k]));
  return std::sqrt(s / (3.0 * double(a.px.size())));
}

double ssim(const Image& a, const Image& b, float exposure) {
  require_same_size(a, b);
  const int w = a.width, h = a.height;
  std::vector<double> la(a.px.size()), lb(a.px.size());
  for (std::size_t i = 0; i < a.px.size(); ++i)
    la[i] = lum_display(a.px[i], exposure), lb[i] = lum_display(b.px[i], exposure);
  constexpr int R = 5;
  double g[2 * R + 1], gs = 0;
  for (int i = -R; i <= R; ++i) gs += g[i + R] = std::exp(-0.5 * i * i / (1.5 * 1.5));
  for (double& x : g) x /= gs;
  // Separable Gaussian blur with clamped borders.
  auto blur = [&](const std::vector<double>& in) {
    std::vector<double> tmp(in.size()), out(in.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0;
        for (int k = -R; k <= R; ++k) s += g[k + R] * in[std::size_t(y) * w + std::clamp(x + k, 0, w - 1)];
        tmp[std::size_t(y) * w + x] = s;
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0;
        for (int k = -R; k <= R; ++k) s += g[k + R] * tmp[std::size_t(std::clamp(y + k, 0, h - 1)) * w + x];
        out[std::size_t(y) * w + x] = s;
      }
    return out;
  };
  std::vector<double> aa(la.size()), bb(la.size()), ab(la.size());
  for (std::size_t i = 0; i < la.size(); ++i)
    aa[i] = la[i] * la[i], bb[i] = lb[i] * lb[i], ab[i] = la[i] * lb[i];
  const auto ma = blur(la), mb = blur(lb), saa = blur(aa), sbb = blur(bb), sab = blur(ab);
  const double c1 = sqr(0.01), c2 = sqr(0.03);
  double sum = 0;
  for (std::size_t i = 0; i < la.size(); ++i) {
    const double va = saa[i] - ma[i] * ma[i], vb = sbb[i] - mb[i] * mb[i], cov = sab[i] - ma[i] * mb[i];
    sum +=
        ((2 * ma[i] * mb[i] + c1) * (2 * cov + c2)) / ((ma[i] * ma[i] + mb[i] * mb[i] + c1) * (va + vb + c2));
  }
  return sum / double(la.size());
}

Image difference_image(const Image& a, const Image& b, float exposure, float gain) {
  require_same_size(a, b);
  Image d(a.width, a.height);
  for (std::size_t i = 0; i < a.px.size(); ++i) {
    const float e = gain * (lum_display(a.px[i], exposure) - lum_display(b.px[i], exposure));
    d.px[i] = e >= 0 ? Rgbf(saturate(e), 0.0f, 0.0f) : Rgbf(0.0f, 0.0f, saturate(-e));
  }
  return d;
}

Image downsample(const Image& img, int f) {
  if (f < 1) throw InputError("downsample factor must be >= 1");
  Image out(img.width / f, img.height / f);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      Rgbf s(0.0f);
      for (int j = 0; j < f; ++j)
        for (int i = 0; i < f; ++i) s += img.at(x * f + i, y * f + j);
      out.at(x, y) = s / float(f * f);
    }
  return out;
}

}  // namespace msh::render

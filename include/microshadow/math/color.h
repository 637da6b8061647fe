// RGB triple with component-wise arithmetic (linear, Rec.709 primaries unless stated).
#pragma once

#include <algorithm>
#include <cmath>

namespace msh {

template <class T>
struct Rgb {
  T r{}, g{}, b{};
  constexpr Rgb() = default;
  constexpr explicit Rgb(T v) : r(v), g(v), b(v) {}
  constexpr Rgb(T r_, T g_, T b_) : r(r_), g(g_), b(b_) {}
  template <class U>
  constexpr explicit Rgb(const Rgb<U>& o) : r(T(o.r)), g(T(o.g)), b(T(o.b)) {}
  constexpr T operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
  constexpr Rgb& operator+=(const Rgb& o) { r += o.r, g += o.g, b += o.b; return *this; }
  constexpr Rgb& operator-=(const Rgb& o) { r -= o.r, g -= o.g, b -= o.b; return *this; }
  constexpr Rgb& operator*=(const Rgb& o) { r *= o.r, g *= o.g, b *= o.b; return *this; }
  constexpr Rgb& operator*=(T s) { r *= s, g *= s, b *= s; return *this; }
};
template <class T> constexpr Rgb<T> operator+(Rgb<T> a, const Rgb<T>& b) { return a += b; }
template <class T> constexpr Rgb<T> operator-(Rgb<T> a, const Rgb<T>& b) { return a -= b; }
template <class T> constexpr Rgb<T> operator*(Rgb<T> a, const Rgb<T>& b) { return a *= b; }
template <class T> constexpr Rgb<T> operator*(Rgb<T> a, T s) { return a *= s; }
template <class T> constexpr Rgb<T> operator*(T s, Rgb<T> a) { return a *= s; }
template <class T> constexpr Rgb<T> operator/(Rgb<T> a, T s) { return a *= (T(1) / s); }
template <class T> constexpr Rgb<T> operator/(const Rgb<T>& a, const Rgb<T>& b) { return {a.r / b.r, a.g / b.g, a.b / b.b}; }
template <class T> constexpr bool operator==(const Rgb<T>& a, const Rgb<T>& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }
template <class T> constexpr Rgb<T> lerp(T t, const Rgb<T>& a, const Rgb<T>& b) { return a + (b - a) * t; }
template <class T> constexpr T max_component(const Rgb<T>& c) { return std::max(c.r, std::max(c.g, c.b)); }
template <class T> constexpr T min_component(const Rgb<T>& c) { return std::min(c.r, std::min(c.g, c.b)); }
// Rec.709 / sRGB luminance.
template <class T> constexpr T luminance(const Rgb<T>& c) { return T(0.2126) * c.r + T(0.7152) * c.g + T(0.0722) * c.b; }
template <class T> bool is_finite(const Rgb<T>& c) { return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b); }

using Rgbf = Rgb<float>;
using Rgbd = Rgb<double>;

// sRGB transfer functions, the exact piecewise curve of IEC 61966-2-1 (linear segment below the breakpoints
// 0.04045 / 0.0031308, power 2.4 with offset 0.055 above). Domain: [0, 1]; negative inputs follow the linear
// segment (finite, sign kept), inputs > 1 follow the power segment.
template <class T>
T srgb_to_linear(T c) {
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}
template <class T>
T linear_to_srgb(T l) {
  return l <= T(0.0031308) ? l * T(12.92) : T(1.055) * std::pow(l, T(1) / T(2.4)) - T(0.055);
}
template <class T>
Rgb<T> srgb_to_linear(const Rgb<T>& c) {
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)};
}
template <class T>
Rgb<T> linear_to_srgb(const Rgb<T>& c) {
  return {linear_to_srgb(c.r), linear_to_srgb(c.g), linear_to_srgb(c.b)};
}

}  // namespace msh

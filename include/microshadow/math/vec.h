// Small vector and frame helpers, templated on the scalar type so references can run in double.
// Convention (docs/theory.md §1): shading frame n = (0,0,1), t = x, b = y; directions point away from the
// surface.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace msh {

template <class T>
inline constexpr T kPi = T(3.14159265358979323846);
template <class T>
inline constexpr T kInvPi = T(0.31830988618379067154);

template <class T>
constexpr T sqr(T x) {
  return x * x;
}
template <class T>
constexpr T clamp(T x, T lo, T hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}
// clamp to [0,1]; NaN maps to 0 (the comparisons are false), so saturate never propagates NaN.
template <class T>
constexpr T saturate(T x) {
  return x > T(0) ? (x < T(1) ? x : T(1)) : T(0);
}
template <class T>
constexpr T lerp(T t, T a, T b) {
  return a + t * (b - a);
}
// sqrt of max(0, x): round-off can make 1 - cos² slightly negative.
template <class T>
T safe_sqrt(T x) {
  return std::sqrt(std::max(x, T(0)));
}
template <class T>
T safe_acos(T x) {
  return std::acos(clamp(x, T(-1), T(1)));
}
template <class T>
T safe_asin(T x) {
  return std::asin(clamp(x, T(-1), T(1)));
}

template <class T>
struct Vec2 {
  T x{}, y{};
  constexpr Vec2() = default;
  constexpr Vec2(T x_, T y_) : x(x_), y(y_) {}
  constexpr T operator[](int i) const { return i == 0 ? x : y; }
};

template <class T>
struct Vec3 {
  T x{}, y{}, z{};
  constexpr Vec3() = default;
  constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  template <class U>
  constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x, y += o.y, z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x, y -= o.y, z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(T s) {
    x *= s, y *= s, z *= s;
    return *this;
  }
};

using Vec2f = Vec2<float>;
using Vec2d = Vec2<double>;
using Vec3f = Vec3<float>;
using Vec3d = Vec3<double>;

template <class T>
constexpr Vec3<T> operator+(Vec3<T> a, const Vec3<T>& b) {
  return a += b;
}
template <class T>
constexpr Vec3<T> operator-(Vec3<T> a, const Vec3<T>& b) {
  return a -= b;
}
template <class T>
constexpr Vec3<T> operator*(Vec3<T> a, T s) {
  return a *= s;
}
template <class T>
constexpr Vec3<T> operator*(T s, Vec3<T> a) {
  return a *= s;
}
template <class T>
constexpr Vec3<T> operator/(Vec3<T> a, T s) {
  return a *= (T(1) / s);
}
template <class T>
constexpr bool operator==(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
template <class T>
constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr T absdot(const Vec3<T>& a, const Vec3<T>& b) {
  const T d = dot(a, b);
  return d < T(0) ? -d : d;
}
template <class T>
constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
T length(const Vec3<T>& a) {
  return std::sqrt(dot(a, a));
}
// Unit vector along a. A zero, non-finite or denormal-length vector returns `fallback` (default +z), so
// callers never divide by zero; check is_finite()/length() first where that case is an input error.
template <class T>
Vec3<T> normalize(const Vec3<T>& a, const Vec3<T>& fallback = Vec3<T>(0, 0, 1)) {
  const T l2 = dot(a, a);
  if (!(l2 > std::numeric_limits<T>::min()) || !std::isfinite(l2)) return fallback;
  return a / std::sqrt(l2);
}
template <class T>
bool is_finite(const Vec3<T>& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
// Mirror w about the unit normal m: 2(w·m)m − w.
template <class T>
constexpr Vec3<T> reflect(const Vec3<T>& w, const Vec3<T>& m) {
  return T(2) * dot(w, m) * m - w;
}

// Spherical helpers for unit vectors in the local shading frame (n = +z).
template <class T>
constexpr T cos_theta(const Vec3<T>& w) {
  return w.z;
}
template <class T>
constexpr T cos2_theta(const Vec3<T>& w) {
  return w.z * w.z;
}
template <class T>
T sin2_theta(const Vec3<T>& w) {
  return std::max(T(0), T(1) - cos2_theta(w));
}
template <class T>
T sin_theta(const Vec3<T>& w) {
  return std::sqrt(sin2_theta(w));
}
template <class T>
T tan2_theta(const Vec3<T>& w) {
  return sin2_theta(w) / cos2_theta(w);
}
// cos/sin of the azimuth; (1, 0) at the pole, where the azimuth is undefined.
template <class T>
T cos_phi(const Vec3<T>& w) {
  const T s = sin_theta(w);
  return s == T(0) ? T(1) : clamp(w.x / s, T(-1), T(1));
}
template <class T>
T sin_phi(const Vec3<T>& w) {
  const T s = sin_theta(w);
  return s == T(0) ? T(0) : clamp(w.y / s, T(-1), T(1));
}
// Unit vector from spherical coordinates about +z.
template <class T>
Vec3<T> spherical_direction(T cos_t, T phi) {
  const T s = safe_sqrt(T(1) - cos_t * cos_t);
  return {s * std::cos(phi), s * std::sin(phi), cos_t};
}

// Orthonormal frame (s, t, n). Local coordinates: x along s, y along t, z along n.
template <class T>
struct Frame {
  Vec3<T> s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  // Any frame around unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited": branchless, no
  // singularity at n = −z).
  static Frame from_z(const Vec3<T>& n) {
    const T sign = std::copysign(T(1), n.z);
    const T a = T(-1) / (sign + n.z);
    const T b = n.x * n.y * a;
    Frame f;
    f.s = {T(1) + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    f.n = n;
    return f;
  }
  // Frame with normal n and the tangent projected from `tangent` (Gram-Schmidt). Falls back to from_z when
  // the tangent is (nearly) parallel to n, zero or not finite.
  static Frame from_zx(const Vec3<T>& n, const Vec3<T>& tangent) {
    const Vec3<T> tp = tangent - dot(tangent, n) * n;
    const T l2 = dot(tp, tp);
    if (!(l2 > T(1e-12)) || !std::isfinite(l2)) return from_z(n);
    Frame f;
    f.n = n;
    f.s = tp / std::sqrt(l2);
    f.t = cross(n, f.s);
    return f;
  }
  Vec3<T> to_local(const Vec3<T>& w) const { return {dot(w, s), dot(w, t), dot(w, n)}; }
  Vec3<T> to_world(const Vec3<T>& w) const { return s * w.x + t * w.y + n * w.z; }
};

using Framef = Frame<float>;
using Framed = Frame<double>;

}  // namespace msh

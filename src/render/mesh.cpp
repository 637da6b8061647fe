// Textures, meshes, tangent generation and the OBJ loader for the renderer.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/render/image.h>
#include <microshadow/render/scene.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace msh::render {

Texture Texture::constant(std::array<float, 4> value, int channels) {
  Texture t(1, 1, channels);
  for (int c = 0; c < channels; ++c) t.at(0, 0, c) = value[c];
  return t;
}

float Texture::texel(int x, int y, int c) const {
  x %= w_, y %= h_;
  if (x < 0) x += w_;
  if (y < 0) y += h_;
  return at(x, y, c < c_ ? c : c_ - 1);
}

namespace {
// Wraps the integer-valued float i into [0, n), exactly for every float: an int64 remainder while
// |i| < 2^62, the (exact) fmod beyond. Non-finite i gives 0: its bilinear weights are NaN, so is the sample.
int wrap_index(float i, int n) {
  if (std::abs(i) < 0x1p62f) {
    const long long k = static_cast<long long>(i) % n;
    return int(k < 0 ? k + n : k);
  }
  if (!std::isfinite(i)) return 0;
  const int k = int(std::fmod(i, float(n)));
  return k < 0 ? k + n : k;
}
}  // namespace

// The four texels and weights of a bilinear lookup at (u, v), wrapped once for every channel.
Texture::Footprint Texture::footprint(float u, float v) const {
  const float x = u * float(w_) - 0.5f, y = v * float(h_) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const int x0 = wrap_index(fx, w_), y0 = wrap_index(fy, h_);
  const int x1 = x0 + 1 == w_ ? 0 : x0 + 1, y1 = y0 + 1 == h_ ? 0 : y0 + 1;
  const auto idx = [&](int xx, int yy) { return (std::size_t(yy) * w_ + xx) * c_; };
  return {{idx(x0, y0), idx(x1, y0), idx(x0, y1), idx(x1, y1)}, x - fx, y - fy};
}

float Texture::filter(const Footprint& f, int c) const {
  const float a = data_[f.i[0] + c], b = data_[f.i[1] + c], d = data_[f.i[2] + c], e = data_[f.i[3] + c];
  return (1 - f.ty) * ((1 - f.tx) * a + f.tx * b) + f.ty * ((1 - f.tx) * d + f.tx * e);
}

float Texture::sample(float u, float v, int c) const {
  if (empty()) return 0.0f;
  return filter(footprint(u, v), c < c_ ? c : c_ - 1);
}

Rgbf Texture::sample_rgb(float u, float v) const {
  if (empty()) return Rgbf(0.0f);
  const Footprint f = footprint(u, v);
  return {filter(f, 0), filter(f, c_ > 1 ? 1 : c_ - 1), filter(f, c_ > 2 ? 2 : c_ - 1)};
}

Texture load_texture(const std::filesystem::path& path, bool srgb) {
  if (!std::filesystem::exists(path))
    throw InputError(fmt::format("{}: texture file not found", path.string()));
  const io::Volume v = io::read_image(path);
  if (v.width < 1 || v.height < 1 || v.channels < 1)
    throw InputError(fmt::format("{}: empty texture", path.string()));
  Texture t(v.width, v.height, v.channels);
  const bool is_png = path.extension() == ".png" || path.extension() == ".PNG";
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
      for (int c = 0; c < v.channels; ++c) {
        float f = v.at(x, y, 0, c);
        if (!std::isfinite(f))
          throw InputError(fmt::format("{}: non-finite texel at ({}, {})", path.string(), x, y));
        if (srgb && is_png && c < 3) f = srgb_decode(f);
        t.at(x, y, c) = f;
      }
  return t;
}

void compute_tangents(Mesh& m) {
  const std::size_t nv = m.p.size();
  std::vector<Vec3f> ts(nv, Vec3f(0, 0, 0)), bs(nv, Vec3f(0, 0, 0));
  for (const auto& t : m.tri) {
    const Vec3f e1 = m.p[t[1]] - m.p[t[0]], e2 = m.p[t[2]] - m.p[t[0]];
    const float du1 = m.uv[t[1]].x - m.uv[t[0]].x, dv1 = m.uv[t[1]].y - m.uv[t[0]].y;
    const float du2 = m.uv[t[2]].x - m.uv[t[0]].x, dv2 = m.uv[t[2]].y - m.uv[t[0]].y;
    const float det = du1 * dv2 - du2 * dv1;
    if (!(std::abs(det) > 1e-20f)) continue;
    const float r = 1.0f / det;
    const Vec3f sdir = (e1 * dv2 - e2 * dv1) * r, tdir = (e2 * du1 - e1 * du2) * r;
    for (int k = 0; k < 3; ++k) {
      // MikkTSpace weights each face's contribution by the corner angle.
      const Vec3f a = normalize(m.p[t[(k + 1) % 3]] - m.p[t[k]]),
                  b = normalize(m.p[t[(k + 2) % 3]] - m.p[t[k]]);
      const float w = safe_acos(dot(a, b));
      ts[t[k]] += normalize(sdir) * w;
      bs[t[k]] += normalize(tdir) * w;
    }
  }
  m.tangent.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    const Framef f = Framef::from_zx(m.n[i], ts[i]);
    const float w = dot(cross(m.n[i], f.s), bs[i]) < 0.0f ? -1.0f : 1.0f;
    m.tangent[i] = {f.s.x, f.s.y, f.s.z, w};
  }
}

Mesh make_uv_sphere(float radius, int segments, int rings) {
  Mesh m;
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i <= segments; ++i) {
      const float u = float(i) / segments, v = float(j) / rings;
      const float phi = 2 * kPi<float> * u, theta = kPi<float> * v;
      const Vec3f n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      m.p.push_back(n * radius);
      m.n.push_back(n);
      m.uv.push_back({u, v});
    }
  const uint32_t row = uint32_t(segments + 1);
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      const uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
      if (j != 0) m.tri.push_back({a, c, b});
      if (j != rings - 1) m.tri.push_back({b, c, d});
    }
  compute_tangents(m);
  return m;
}

Mesh make_cylinder(float radius, float height, int segments) {
  Mesh m;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= segments; ++i) {
      const float u = float(i) / segments, phi = 2 * kPi<float> * u;
      const Vec3f n(std::cos(phi), std::sin(phi), 0.0f);
      m.p.push_back(Vec3f(n.x * radius, n.y * radius, (0.5f - float(j)) * height));
      m.n.push_back(n);
      m.uv.push_back({u, float(j)});
    }
  const uint32_t row = uint32_t(segments + 1);
  for (int i = 0; i < segments; ++i) {
    const uint32_t a = i, b = i + 1, c = row + i, d = row + i + 1;
    m.tri.push_back({a, c, b});
    m.tri.push_back({b, c, d});
  }
  compute_tangents(m);
  return m;
}

Mesh load_obj(const std::filesystem::path& path) {
  require_regular_file(path, "OBJ file ");
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open OBJ file", path.string()));
  std::vector<Vec3f> P, N;
  std::vector<Vec2f> UV;
  Mesh m;
  std::map<std::tuple<long, long, long>, uint32_t> corners;
  std::string line;
  int lineno = 0;
  auto bad = [&](const std::string& what) {
    return InputError(fmt::format("{}:{}: malformed OBJ: {}", path.string(), lineno, what));
  };
  auto fix = [&](long idx, std::size_t n) -> long {
    const long r = idx > 0 ? idx - 1 : long(n) + idx;
    if (idx == 0 || r < 0 || r >= long(n)) throw bad(fmt::format("index {} out of range", idx));
    return r;
  };
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    if (tag == "v" || tag == "vn") {
      float x, y, z;
      if (!(ls >> x >> y >> z) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        throw bad("expected 3 finite numbers after '" + tag + "'");
      (tag == "v" ? P : N).push_back({x, y, z});
    } else if (tag == "vt") {
      float u, v;
      if (!(ls >> u >> v) || !std::isfinite(u) || !std::isfinite(v))
        throw bad("expected 2 finite numbers after 'vt'");
      UV.push_back({u, 1.0f - v});  // OBJ v points up; our v runs down the image
    } else if (tag == "f") {
      std::vector<uint32_t> poly;
      std::string corner;
      while (ls >> corner) {
        long vi = 0, ti = 0, ni = 0;
        const int got = std::sscanf(corner.c_str(), "%ld/%ld/%ld", &vi, &ti, &ni);
        if (got < 1) {
          if (std::sscanf(corner.c_str(), "%ld//%ld", &vi, &ni) != 2)
            throw bad("bad face corner '" + corner + "'");
        } else if (got == 1 && corner.find("//") != std::string::npos) {
          if (std::sscanf(corner.c_str(), "%ld//%ld", &vi, &ni) != 2)
            throw bad("bad face corner '" + corner + "'");
        }
        const long pv = fix(vi, P.size());
        const long tv = ti ? fix(ti, UV.size()) : -1, nv = ni ? fix(ni, N.size()) : -1;
        // Corners sharing (v, vt, vn) share a vertex, so tangents are accumulated across faces (MikkTSpace).
        const auto key = std::make_tuple(pv, tv, nv);
        auto it = corners.find(key);
        if (it == corners.end()) {
          m.p.push_back(P[pv]);
          m.uv.push_back(tv >= 0 ? UV[tv] : Vec2f(0, 0));
          m.n.push_back(nv >= 0 ? normalize(N[nv]) : Vec3f(0, 0, 0));
          it = corners.emplace(key, uint32_t(m.p.size() - 1)).first;
        }
        poly.push_back(it->second);
      }
      if (poly.size() < 3) throw bad("face with fewer than 3 vertices");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) m.tri.push_back({poly[0], poly[k], poly[k + 1]});
    }  // other tags (o, g, s, usemtl, mtllib) are ignored
  }
  if (m.tri.empty()) throw InputError(fmt::format("{}: OBJ file has no faces", path.string()));
  // Missing normals: the face normal.
  for (const auto& t : m.tri) {
    const Vec3f fn = normalize(cross(m.p[t[1]] - m.p[t[0]], m.p[t[2]] - m.p[t[0]]));
    for (int k = 0; k < 3; ++k)
      if (m.n[t[k]] == Vec3f(0, 0, 0)) m.n[t[k]] = fn;
  }
  compute_tangents(m);
  return m;
}

}  // namespace msh::render

// What the study's stages share (src/study/study.cpp plans, cell.cpp renders and measures, results.cpp
// aggregates): the scene's geometry constants and frames, and small helpers. Not installed.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/study/study.h>

#include <chrono>
#include <ctime>
#include <nlohmann/json.hpp>
#include <string>

namespace msh::study::detail {

inline constexpr float kTileWorld = 2.0f;  // world size of one texture tile
inline constexpr float kCylRadius = kTileWorld / (2 * kPi<float>), kCylRotate = 0.5f * kPi<float>;

inline constexpr const char* kComponentName[3] = {"total", "diffuse", "specular"};
inline constexpr const char* kRegionName[3] = {"rough", "smooth", "whole"};

// The shape's frame at the view's centre: P0 on the mean surface, T = ∂P/∂u, B = ∂P/∂v, N the normal. Lights
// and the camera are placed in this frame, so "elevation" is above the tangent plane at the view's centre.
// plane: z = 0, spanning an odd number of tiles each way (3 unless a view reaches further), its centre at u =
// half a tile (the rough/smooth boundary).
// cylinder: axis +z, circumference and length one tile (texels square), rotated so that u = 0.5 (the
// rough/smooth boundary) faces the camera at -y; B = ∂P/∂v points down the axis.
struct Frame {
  Vec3f P0, T, B, N;
};
inline Frame frame_of(const std::string& shape) {
  if (shape == "cylinder") return {{0, -kCylRadius, 0}, {1, 0, 0}, {0, 0, -1}, {0, -1, 0}};
  return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}

// The area-light section is on (StudyConfig's area_* comment).
inline bool area_section(const StudyConfig& c) {
  return !c.area_radii_deg.empty() || !c.area_planar_radii_deg.empty();
}

// JSON cannot hold NaN: regions without signal are written as null.
void scrub(nlohmann::json& j);

inline double secs_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// Process CPU time (all threads), to report cost on a loaded machine.
inline double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace msh::study::detail

// Helpers shared by the study tests (test_study, test_study_cell).
#pragma once

#include <microshadow/study/study.h>

#include <string>
#include <utility>
#include <vector>

namespace msh::test {

// A tiny plan of quick_config(): one procedural material on the plane under directional lights at azimuth 0
// (no point or sphere light), 4 AO rays, a footprint of 4 pixels, 16 to 32 ground-truth samples per pixel.
inline study::StudyConfig tiny_plane_study(const std::string& name, const std::string& material,
                                           int fine_size, std::vector<int> scales,
                                           std::vector<double> elevations, int image_size) {
  study::StudyConfig c = study::quick_config();
  c.name = name;
  c.materials = {material};
  c.shapes = {"plane"};
  c.fine_size = fine_size;
  c.ao_rays = 4;
  c.scales = std::move(scales);
  c.elevations = std::move(elevations);
  c.azimuths = {0};
  c.point_light = c.sphere_light = false;
  c.image_size = image_size;
  c.footprint = 4;
  c.gt_spp = 16;
  c.gt_max_spp = 32;
  return c;
}

}  // namespace msh::test

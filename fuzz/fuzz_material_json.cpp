// libFuzzer target: the readers of a texture set's material.json (written by gen-material, edited by users):
// study::user_material_from_folder (`study --material`), the viewer's texture-set loading (`view
// --material`, through view::viewer_data_files) and the scene reader's lookup beside a height map
// (render::parse_scene on a scene naming DIR/height.png). The folder is a real 8 × 8 texture set with 21
// directional channels, written once per process; each input replaces its material.json. A value or
// msh::InputError; nothing else.
#include <microshadow/io/error.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>
#include <microshadow/study/study.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "../src/view/viewer_server.h"
#include "fuzz_common.h"

namespace fs = std::filesystem;

namespace {
fs::path texture_set_dir() {
  const fs::path dir = msh::fuzz::scratch_path("set", "");
  msh::render::GenOptions o;
  o.kind = "plaster";
  o.size = 8;
  o.ao_rays = 4;
  o.directional_azimuths = 8;
  o.directional_view = true;
  msh::render::write_texture_set(dir, msh::render::generate_texture_set(o));
  return dir;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fs::path dir = texture_set_dir();
  msh::fuzz::write_bytes(dir / "material.json", data, size);
  try {
    const msh::study::UserMaterial u = msh::study::user_material_from_folder(dir);
    if (!std::isfinite(u.depth_texels)) std::abort();
  } catch (const msh::InputError&) {
  }
  try {
    msh::view::ViewerOptions o;
    o.assets = fs::path(MSH_FUZZ_ASSET_DIR).parent_path();  // the source tree: web/, shaders/glsl/
    o.material = dir;
    o.lut = dir / "no_table.npy";  // the table loads after the material: an InputError, not a bake per input
    (void)msh::view::viewer_data_files(o);
  } catch (const msh::InputError&) {
  }
  try {
    const std::string scene =
        R"({"camera": {"eye": [0, -1, 1], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
            "materials": {"m": {"height": ")" +
        (dir / "height.png").string() + R"("}},
            "objects": [{"type": "plane", "material": "m"}],
            "lights": [{"type": "directional", "elevation_deg": 30, "azimuth_deg": 0}],
            "settings": {"width": 8, "height": 8, "spp": 1}})";
    (void)msh::render::parse_scene(scene, "fuzz.json", dir);
  } catch (const msh::InputError&) {
  }
  return 0;
}

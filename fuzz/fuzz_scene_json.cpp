// libFuzzer target: render::parse_scene (the scene JSON reader). Relative asset paths resolve against the
// repository's examples/ directory (MSH_FUZZ_ASSET_DIR), so that the OBJ and texture branches are reachable.
// A Scene or msh::InputError; nothing else.
#include <microshadow/io/error.h>
#include <microshadow/render/scene.h>

#include <string>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)msh::render::parse_scene(text, "fuzz.json", MSH_FUZZ_ASSET_DIR);
  } catch (const msh::InputError&) {
  }
  return 0;
}

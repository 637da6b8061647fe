// libFuzzer target: render::load_obj (Wavefront OBJ). A Mesh or msh::InputError; nothing else.
#include <microshadow/io/error.h>
#include <microshadow/render/scene.h>

#include <cstdlib>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = msh::fuzz::input_file("mesh", ".obj", data, size);
  try {
    (void)msh::render::load_obj(path);
  } catch (const msh::InputError&) {
  }
  return 0;
}

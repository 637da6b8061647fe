// libFuzzer target: io::read_volume over one file format, chosen at build time by MSH_FUZZ_EXT (".dds",
// ".ktx2", ".exr", ".npy", ".png"). The only acceptable outcomes are a Volume or msh::InputError; any other
// exception, a crash or a sanitizer report is a finding.
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include "fuzz_common.h"

#ifndef MSH_FUZZ_EXT
#error "define MSH_FUZZ_EXT, e.g. \".dds\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = msh::fuzz::input_file("volume", MSH_FUZZ_EXT, data, size);
  try {
    msh::fuzz::check_volume(msh::io::read_volume(path));
  } catch (const msh::InputError&) {
  }
  return 0;
}

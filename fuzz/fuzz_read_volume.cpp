// libFuzzer target: io::read_volume over one file format, chosen at build time by MSH_FUZZ_EXT (".dds",
// ".ktx2", ".exr", ".npy", ".png"). The only acceptable outcomes are a Volume or msh::InputError; any other
// exception, a crash or a sanitizer report is a finding.
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <cmath>
#include <cstdlib>

#include "fuzz_common.h"

#ifndef MSH_FUZZ_EXT
#error "define MSH_FUZZ_EXT, e.g. \".dds\""
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto path = msh::fuzz::scratch_path("volume", MSH_FUZZ_EXT);
  msh::fuzz::write_bytes(path, data, size);
  try {
    const msh::io::Volume v = msh::io::read_volume(path);
    // The reader's contract (docs/formats.md): consistent sizes and finite values.
    if (v.data.size() != v.texel_count() * std::size_t(v.channels)) std::abort();
    for (float x : v.data)
      if (!std::isfinite(x)) std::abort();
  } catch (const msh::InputError&) {
  }
  return 0;
}

// libFuzzer target: lut::load_micro_shadowing_lut (table + JSON sidecar) and a lookup through the table's
// view. Input: the sidecar's text, a NUL byte, then the table as an .npy file (no NUL: no sidecar, whole
// input is the table). A table or msh::InputError; a loaded table must give finite lookups in [0, 1].
#include <microshadow/io/error.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto table = msh::fuzz::scratch_path("lut", ".npy");
  static const auto sidecar = msh::lut::sidecar_path(table);
  const auto* nul = static_cast<const std::uint8_t*>(std::memchr(data, 0, size));
  std::error_code ec;
  if (nul) {
    msh::fuzz::write_bytes(sidecar, data, std::size_t(nul - data));
    msh::fuzz::write_bytes(table, nul + 1, size - std::size_t(nul + 1 - data));
  } else {
    std::filesystem::remove(sidecar, ec);
    msh::fuzz::write_bytes(table, data, size);
  }
  try {
    const msh::lut::MicroShadowingLut lut = msh::lut::load_micro_shadowing_lut(table);
    const auto view = lut.view();
    for (double v : {0.0, 0.37, 1.0})
      for (double nl : {0.05, 0.5, 1.0}) {
        const double s = msh::lut::sample_micro_shadowing(view, v, nl, 0.8, 0.5);
        const double a = msh::lut::sample_micro_shadowing_azimuth(view, v, nl, 0.8, 0.5, -0.3);
        if (!(s >= 0 && s <= 1) || !(a >= 0 && a <= 1)) std::abort();
      }
  } catch (const msh::InputError&) {
  }
  return 0;
}

// NPY output straight from memory (io/texture.h's write_volume copies into a Volume first).
#pragma once

#include <filesystem>
#include <span>

namespace msh::io {

// write_volume(path, v, FileFormat::Npy) of a volume whose data would be `data` (width × height × depth ×
// channels values, the io::Volume layout), written from `data` itself: no copy of the values is made.
// InputError as write_volume (dimensions, a size mismatch, a non-finite value; nothing written then).
void write_npy(const std::filesystem::path& path, std::span<const float> data, int width, int height, int depth,
               int channels);

}  // namespace msh::io

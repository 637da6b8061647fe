// Texture and image I/O: DDS, KTX2, EXR, NPY, C header, PNG (layouts in docs/formats.md).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace msh::io {

// A 3D (depth > 1) or 2D (depth == 1) float texture, channels interleaved, x fastest:
// data[((z*height + y)*width + x)*channels + c]. NPY export shape is (depth, height, width, channels).
struct Volume {
  int width = 0, height = 0, depth = 1, channels = 4;
  std::vector<float> data;

  Volume() = default;
  Volume(int w, int h, int d, int c)
      : width(w), height(h), depth(d), channels(c), data(std::size_t(w) * h * d * c, 0.0f) {}
  std::size_t index(int x, int y, int z, int c) const {
    return ((std::size_t(z) * height + y) * width + x) * channels + c;
  }
  float& at(int x, int y, int z, int c) { return data[index(x, y, z, c)]; }
  float at(int x, int y, int z, int c) const { return data[index(x, y, z, c)]; }
  std::size_t texel_count() const { return std::size_t(width) * height * depth; }
};

enum class FileFormat { Dds, Ktx2, Exr, Npy, CHeader, Png };
enum class PixelFormat {
  RGBA8Unorm,
  RGBA16Float,
  RGBA32Float,
  RG16Float,
  RG32Float,
  R16Float,
  R32Float,
  R8Unorm,
  RG8Unorm,
  BC4Unorm,  // block-compressed (io/bc4.h): 1 channel, 8 bytes per 4 × 4 texels; DDS and KTX2, 2D only
  BC5Unorm   // two BC4 blocks (red, then green): 2 channels, 16 bytes per 4 × 4 texels
};

// By extension (.dds .ktx2 .exr .npy .h/.hpp .png, case-insensitive); InputError otherwise.
FileFormat file_format_from_path(const std::filesystem::path& path);
// "dds", "ktx2", "exr", "npy", "h", "png"; InputError otherwise.
FileFormat file_format_from_name(const std::string& name);
// "rgba8", "rgba16f", "rgba32f", "rg16f", "rg32f", "r16f", "r32f", "r8", "rg8", "bc4", "bc5"; InputError
// otherwise.
PixelFormat pixel_format_from_name(const std::string& name);
std::string pixel_format_name(PixelFormat pf);
int pixel_format_channels(PixelFormat pf);

// Writes atomically (io::AtomicPath/write_file_atomic). Channel count must match the PixelFormat
// (InputError). Non-finite values are an error (InputError), never written. UNORM: round-to-nearest of
// saturate(x)*255. BC4/BC5: io::bc4_encode per channel (partial 4 × 4 blocks repeat the edge texels; 3D
// volumes are an InputError); read back decoded to floats. The PixelFormat applies to DDS and KTX2; EXR
// stores half for *16Float and float otherwise; NPY and C header always store float32 (the exact values); PNG
// stores 8 bits for *8Unorm and 16 bits otherwise. `symbol` is the C identifier used by the C header writer.
void write_volume(const std::filesystem::path& path, const Volume& v, FileFormat ff,
                  PixelFormat pf = PixelFormat::RGBA16Float, const std::string& symbol = "lut");
// Reads DDS, KTX2, EXR, NPY, PNG written by us (format by extension) → floats. InputError on any failure.
Volume read_volume(const std::filesystem::path& path);

// A 2D texture with its mip chain as DDS or KTX2 (by extension; atomically): levels[0] the full texture,
// level i of max(1, w >> i) × max(1, h >> i) texels with the same channels (at most 1 + log2(max side)
// levels). DDS: dwMipMapCount and DDSCAPS_COMPLEX | DDSCAPS_MIPMAP, level 0 first; KTX2: levelCount and the
// level index, data stored smallest level first as the KTX 2.0 specification requires. InputError otherwise
// (and as write_volume).
void write_texture_mips(const std::filesystem::path& path, const std::vector<Volume>& levels, PixelFormat pf);
// Level `level` of a DDS or KTX2 file (0 = what read_volume returns). InputError when the file has no such
// level or on any failure.
Volume read_texture_level(const std::filesystem::path& path, int level);

// 2D images for the renderer: PNG (8/16-bit gray/GA/RGB/RGBA via libpng; values returned as-is in [0,1], no
// color conversion) and EXR (half or float RGB/RGBA via OpenEXR). Volume with depth = 1.
Volume read_image(const std::filesystem::path& path);  // .png or .exr; InputError naming the file on failure
void write_png(const std::filesystem::path& path, const Volume& image_in_0_1, int bits = 8);  // 1–4 channels
void write_exr(const std::filesystem::path& path, const Volume& image, bool half = true);

}  // namespace msh::io

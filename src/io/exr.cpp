// OpenEXR images and volumes. A volume of depth D is stored as one scanline image of width W and height H*D
// (slice z occupies rows z*H .. z*H + H - 1) with the int attributes "microshadow:depth" = D and
// "microshadow:sliceHeight" = H. Channels: 1 → Y, 2 → R G, 3 → R G B, 4 → R G B A; half or float, ZIP.
#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>

#include <cstring>
#include <exception>

#include "texture_internal.h"

namespace msh::io::codecs {
namespace fs = std::filesystem;

namespace {
constexpr const char* kDepthAttr = "microshadow:depth";
constexpr const char* kSliceAttr = "microshadow:sliceHeight";

std::vector<std::string> channel_names(int channels) {
  switch (channels) {
    case 1:
      return {"Y"};
    case 2:
      return {"R", "G"};
    case 3:
      return {"R", "G", "B"};
    default:
      return {"R", "G", "B", "A"};
  }
}
}  // namespace

void write_exr_volume(const fs::path& path, const Volume& v, bool half) {
  validate_volume(v, path, 1, 4);
  const long long total_h = (long long)v.height * v.depth;
  if (total_h > (1 << 30)) fail(path, "volume too tall for an EXR image");
  const std::vector<std::string> names = channel_names(v.channels);
  const std::size_t xs_f = sizeof(float) * v.channels, ys_f = xs_f * v.width;

  std::vector<Imath::half> hbuf;
  if (half) {
    hbuf.resize(v.data.size());
    for (std::size_t i = 0; i < v.data.size(); ++i) {
      hbuf[i] = Imath::half(v.data[i]);
      if (hbuf[i].isInfinity())
        fail(path, fmt::format("value {} at index {} overflows half float (max 65504); nothing written",
                               v.data[i], i));
    }
  }
  AtomicPath ap(path);
  try {
    Imf::Header header(v.width, int(total_h));
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert(kDepthAttr, Imf::IntAttribute(v.depth));
    header.insert(kSliceAttr, Imf::IntAttribute(v.height));
    Imf::FrameBuffer fb;
    for (int c = 0; c < v.channels; ++c) {
      if (half) {
        header.channels().insert(names[c], Imf::Channel(Imf::HALF));
        const std::size_t xs = sizeof(Imath::half) * v.channels;
        fb.insert(names[c],
                  Imf::Slice(Imf::HALF, reinterpret_cast<char*>(hbuf.data() + c), xs, xs * v.width));
      } else {
        header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
        fb.insert(names[c],
                  Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(v.data.data() + c)),
                             xs_f, ys_f));
      }
    }
    {
      Imf::OutputFile out(ap.temp().c_str(), header);
      out.setFrameBuffer(fb);
      out.writePixels(int(total_h));
    }
  } catch (const std::exception& e) {
    fail(path, fmt::format("cannot write EXR: {}", e.what()));
  }
  ap.commit();
}

namespace {
// The value size OpenEXR's typed attributes read whatever the declared size (they parse by content): fixed-
// size types; 0 for a type read by its declared size (string, floatvector, unknown types kept opaque) or
// walked below (chlist, preview, stringvector). OpenEXR 3.1's attribute types (Kainz et al., "Technical
// Introduction to OpenEXR"; "OpenEXR File Layout").
std::size_t fixed_attribute_size(std::string_view type) {
  static constexpr std::pair<std::string_view, std::size_t> kFixed[] = {{"box2i", 16},
                                                                        {"box2f", 16},
                                                                        {"chromaticities", 32},
                                                                        {"compression", 1},
                                                                        {"deepImageState", 1},
                                                                        {"double", 8},
                                                                        {"envmap", 1},
                                                                        {"float", 4},
                                                                        {"int", 4},
                                                                        {"keycode", 28},
                                                                        {"lineOrder", 1},
                                                                        {"m33f", 36},
                                                                        {"m33d", 72},
                                                                        {"m44f", 64},
                                                                        {"m44d", 128},
                                                                        {"rational", 8},
                                                                        {"tiledesc", 9},
                                                                        {"timecode", 8},
                                                                        {"v2i", 8},
                                                                        {"v2f", 8},
                                                                        {"v2d", 16},
                                                                        {"v3i", 12},
                                                                        {"v3f", 12},
                                                                        {"v3d", 24}};
  for (const auto& [name, size] : kFixed)
    if (name == type) return size;
  return 0;
}

// OpenEXR allocates each header attribute's declared size before reading it: a 500-byte file declaring a
// ~2 GB attribute of an unknown type made every read take seconds under ASan (fuzzing: a 10 s timeout).
// Walk the header(s) first and require every declared size to fit in the file. OpenEXR parses a chlist, a
// preview and the fixed-size types by their content, not by the declared size, so the walk requires the
// two to agree: otherwise the two parsers fall out of step and the attribute OpenEXR reads next is one this
// walk never saw (fuzzing found that twice: a window and a 1.6 GB attribute behind a chlist). The InputFile
// constructor also allocates and clears line buffers for the whole data window (a 312-byte file declaring
// a 10⁹ × 65537 window timed out the same way), so every data window is checked against our limits here.
void check_exr_header(const fs::path& path) {
  const std::vector<std::byte> bytes = read_file(path);
  const ByteReader r{bytes, &path};
  if (r.u32(0) != 20000630u) fail(path, "not an OpenEXR file (bad magic)");
  const bool multipart = (r.u32(4) & 0x1000u) != 0;
  std::size_t pos = 8;
  const auto read_string = [&] {  // a NUL-terminated name
    const std::size_t start = pos;
    for (r.require(pos, 1); bytes[pos] != std::byte{0}; r.require(pos, 1)) ++pos;
    return std::string_view(reinterpret_cast<const char*>(bytes.data()) + start, pos++ - start);
  };
  const auto corrupt = [&](std::string_view raw_name, std::string_view type, std::uint32_t size) {
    std::string name(raw_name);
    for (char& c : name)
      if (c < ' ' || c > '~') c = '?';  // fuzzed names hold control bytes
    fail(path, fmt::format("EXR header attribute '{}' of type {} declares {} bytes, which its value does not "
                           "fill (corrupt header)",
                           name, type, size));
  };
  for (bool more = true; more;) {
    bool empty = true;
    for (std::string_view name; !(name = read_string()).empty();) {  // an empty name ends the header
      empty = false;
      const std::string_view type = read_string();
      const std::uint32_t size = r.u32(pos);
      pos += 4;
      if (size > bytes.size() - pos)
        fail(path, fmt::format("EXR header attribute of {} bytes in a file of {} bytes (corrupt header)",
                               size, bytes.size()));
      const std::size_t end = pos + size;
      if (const std::size_t fixed = fixed_attribute_size(type); fixed != 0) {
        if (size != fixed) corrupt(name, type, size);
      } else if (type == "chlist") {  // {name, int32 type, uint8 linear, 3 reserved, int32 x/y sampling}*, ""
        while (!read_string().empty()) pos += 16;
        if (pos != end) corrupt(name, type, size);
      } else if (type == "preview") {  // uint32 width, height, then RGBA8 texels (OpenEXR: w·h in 32 bits)
        if (size < 8 || r.u32(pos) > (1u << 16) || r.u32(pos + 4) > (1u << 16) ||
            std::uint64_t(r.u32(pos)) * r.u32(pos + 4) * 4 != size - 8)
          corrupt(name, type, size);
      } else if (type == "stringvector") {  // {int32 length, bytes}* filling the value
        for (std::size_t at = pos; at != end; at += 4 + r.u32(at))
          if (end - at < 4 || r.u32(at) > end - at - 4) corrupt(name, type, size);
      } else if (type == "idmanifest") {  // compressed, with an uncompressed size OpenEXR allocates up front
        fail(path, "EXR ID manifests (idmanifest attributes) are not supported");
      }
      pos = end;
    }
    more = multipart && !empty;  // multi-part: headers follow one another, an empty one ends the list
  }
  // Every "dataWindow" box2i attribute anywhere in the file (a second line of defence should another
  // attribute type parse by content): the window stacks a volume's slices (height = depth × slice height),
  // so width and total size only.
  static constexpr char kWindow[] = "dataWindow\0box2i\0\x10\0\0\0";
  constexpr std::size_t kLen = sizeof(kWindow) - 1;
  for (std::size_t at = 0; at + kLen + 16 <= bytes.size(); ++at) {
    if (std::memcmp(bytes.data() + at, kWindow, kLen) != 0) continue;
    const std::size_t v = at + kLen;
    const auto i32 = [&](std::size_t o) { return (long long)std::int32_t(r.u32(o)); };
    const long long w = i32(v + 8) - i32(v) + 1, h = i32(v + 12) - i32(v + 4) + 1;
    check_dimensions(path, w, 1, 1, 1);
    if (h < 1 || std::size_t(w) * std::size_t(h) > kMaxElements)
      fail(path, fmt::format("EXR data window {}x{} exceeds the size limit", w, h));
  }
}
}  // namespace

Volume read_exr(const fs::path& path, bool as_volume) {
  require_regular_file(path);
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail(path, "cannot open file");
  check_exr_header(path);
  try {
    Imf::InputFile in(path.c_str());
    const Imf::Header& h = in.header();
    const Imath::Box2i dw = h.dataWindow();
    const long long W = (long long)dw.max.x - dw.min.x + 1, Htot = (long long)dw.max.y - dw.min.y + 1;
    const Imf::ChannelList& cl = h.channels();
    std::vector<std::string> use;
    auto has = [&](const char* n) { return cl.findChannel(n) != nullptr; };
    if (has("R") && has("G") && has("B")) {
      use = {"R", "G", "B"};
      if (has("A")) use.push_back("A");
    } else if (has("R") && has("G")) {
      use = {"R", "G"};
    } else if (has("Y")) {
      use = {"Y"};
      if (has("A")) use.push_back("A");
    } else if (has("R")) {
      use = {"R"};
    } else {
      int n = 0;
      for (auto it = cl.begin(); it != cl.end(); ++it) ++n, use = {it.name()};
      if (n != 1) fail(path, "unsupported EXR channel layout (expected Y, YA, R, RG, RGB or RGBA)");
    }
    long long D = 1, H = Htot;
    if (as_volume) {
      const auto* da = h.findTypedAttribute<Imf::IntAttribute>(kDepthAttr);
      if (da && da->value() > 1) {
        D = da->value();
        if (Htot % D != 0)
          fail(path, fmt::format("image height {} is not a multiple of {} = {}", Htot, kDepthAttr, D));
        H = Htot / D;
      }
    }
    check_dimensions(path, W, H, D, (long long)use.size());
    // A corrupt header can claim a data window far larger than the file encodes, and OpenEXR then fills the
    // missing rows with zeros: a 1.4 KB file claiming 65535×512 read as a 134 MB volume (fuzzing: the EXR
    // target peaked at 271 MB RSS on ≤ 521-byte inputs). Bound the raw size by the file size times a ratio no
    // lossless EXR codec reaches (zlib < 1032:1, RLE 64:1, PIZ < 1000:1; B44 21:1) before allocating. DWA
    // (lossy DCT) has no such bound; the 2^28-value limit still applies.
    if (h.compression() != Imf::DWAA_COMPRESSION && h.compression() != Imf::DWAB_COMPRESSION) {
      double raw = 0;
      for (const auto& n : use) {
        const Imf::Channel& ch = *cl.findChannel(n);
        raw += double(W) * double(Htot) * (ch.type == Imf::HALF ? 2 : 4) /
               (double(std::max(1, ch.xSampling)) * double(std::max(1, ch.ySampling)));
      }
      const double size = double(fs::file_size(path, ec));
      if (!ec && raw > 4096.0 * size + 65536.0)
        fail(path, fmt::format("EXR data window {}x{} cannot be held in a file of {} bytes (corrupt header)",
                               W, Htot, size));
    }
    Volume v(int(W), int(H), int(D), int(use.size()));
    const std::size_t xs = sizeof(float) * v.channels, ys = xs * v.width;
    Imf::FrameBuffer fb;
    for (int c = 0; c < v.channels; ++c)
      fb.insert(use[c], Imf::Slice::Make(Imf::FLOAT, v.data.data() + c, dw, xs, ys));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return v;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    fail(path, fmt::format("cannot read EXR: {}", e.what()));
  }
}

}  // namespace msh::io::codecs

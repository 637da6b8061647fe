// PNG via libpng: gray, gray+alpha, RGB, RGBA at 8 or 16 bits, values stored as-is (no gamma/sRGB chunk, no
// color conversion). A volume of depth D is stored as one image of height H*D (slice z in rows z*H ..) with
// the tEXt chunk "microshadow:depth" = D. libpng reports errors by longjmp, so each libpng call sequence runs
// in a small function holding no C++ objects with destructors.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstdlib>

#include "texture_internal.h"

namespace msh::io::codecs {
namespace fs = std::filesystem;

namespace {
constexpr const char* kDepthKey = "microshadow:depth";

struct PngCtx {
  png_structp png = nullptr;
  png_infop info = nullptr;
  std::FILE* file = nullptr;
  char message[256] = "";
};

void on_error(png_structp png, png_const_charp msg) {
  auto* ctx = static_cast<PngCtx*>(png_get_error_ptr(png));
  std::snprintf(ctx->message, sizeof ctx->message, "%s", msg ? msg : "libpng error");
  png_longjmp(png, 1);
}
void on_warning(png_structp, png_const_charp) {}

struct WriteJob {
  png_uint_32 width, height;
  int bit_depth, color_type;
  png_bytep* rows;
  const char* depth_text;  // nullptr: no text chunk
};

bool png_write_all(PngCtx* ctx, const WriteJob* job) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_init_io(ctx->png, ctx->file);
  png_set_IHDR(ctx->png, ctx->info, job->width, job->height, job->bit_depth, job->color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (job->depth_text) {
    png_text text{};
    text.compression = PNG_TEXT_COMPRESSION_NONE;
    text.key = const_cast<char*>(kDepthKey);
    text.text = const_cast<char*>(job->depth_text);
    png_set_text(ctx->png, ctx->info, &text, 1);
  }
  png_write_info(ctx->png, ctx->info);
  png_write_image(ctx->png, job->rows);
  png_write_end(ctx->png, nullptr);
  return true;
}

struct ReadInfo {
  png_uint_32 width = 0, height = 0;
  int channels = 0, bit_depth = 0;
  std::size_t rowbytes = 0;
  long depth = 1;
};

bool png_read_header(PngCtx* ctx, ReadInfo* out) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_init_io(ctx->png, ctx->file);
  png_set_user_limits(ctx->png, kMaxDimension, kMaxDimension);
  png_read_info(ctx->png, ctx->info);
  const int color_type = png_get_color_type(ctx->png, ctx->info);
  const int bit_depth = png_get_bit_depth(ctx->png, ctx->info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(ctx->png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(ctx->png);
  if (png_get_valid(ctx->png, ctx->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(ctx->png);
  png_read_update_info(ctx->png, ctx->info);
  out->width = png_get_image_width(ctx->png, ctx->info);
  out->height = png_get_image_height(ctx->png, ctx->info);
  out->channels = png_get_channels(ctx->png, ctx->info);
  out->bit_depth = png_get_bit_depth(ctx->png, ctx->info);
  out->rowbytes = png_get_rowbytes(ctx->png, ctx->info);
  png_textp text = nullptr;
  int num_text = 0;
  if (png_get_text(ctx->png, ctx->info, &text, &num_text) > 0) {
    for (int i = 0; i < num_text; ++i)
      if (std::strcmp(text[i].key, kDepthKey) == 0 && text[i].text)
        out->depth = std::strtol(text[i].text, nullptr, 10);
  }
  return true;
}

bool png_read_rows(PngCtx* ctx, png_bytep* rows) {
  if (setjmp(png_jmpbuf(ctx->png))) return false;
  png_read_image(ctx->png, rows);
  png_read_end(ctx->png, nullptr);
  return true;
}
}  // namespace

void write_png_volume(const fs::path& path, const Volume& v, int bits) {
  validate_volume(v, path, 1, 4);
  const long long total_h = (long long)v.height * v.depth;
  if (total_h > kMaxDimension) fail(path, "volume too tall for a PNG image");
  const int bpc = bits / 8;
  const std::size_t row_bytes = std::size_t(v.width) * v.channels * bpc;
  std::vector<png_byte> pixels(row_bytes * std::size_t(total_h));
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    if (bits == 8) {
      pixels[i] = to_unorm8(v.data[i]);
    } else {
      const std::uint16_t q = to_unorm16(v.data[i]);
      pixels[2 * i] = png_byte(q >> 8);  // PNG samples are big-endian
      pixels[2 * i + 1] = png_byte(q & 0xff);
    }
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(total_h));
  for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = pixels.data() + y * row_bytes;
  static constexpr int kColorType[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                       PNG_COLOR_TYPE_RGB_ALPHA};
  const std::string depth_text = std::to_string(v.depth);
  const WriteJob job{
      png_uint_32(v.width),       png_uint_32(total_h), bits,
      kColorType[v.channels - 1], rows.data(),          v.depth > 1 ? depth_text.c_str() : nullptr};

  AtomicPath ap(path);
  PngCtx ctx;
  ctx.file = std::fopen(ap.temp().c_str(), "wb");
  if (!ctx.file) fail(path, "cannot open for writing");
  ctx.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning);
  if (ctx.png) ctx.info = png_create_info_struct(ctx.png);
  const bool ok = ctx.png && ctx.info && png_write_all(&ctx, &job);
  png_destroy_write_struct(&ctx.png, &ctx.info);
  const bool closed = std::fclose(ctx.file) == 0;
  if (!ok) fail(path, fmt::format("cannot write PNG: {}", ctx.message));
  if (!closed) fail(path, "cannot write PNG: write failed");
  ap.commit();
}

Volume read_png(const fs::path& path, bool as_volume) {
  require_regular_file(path);
  PngCtx ctx;
  ctx.file = std::fopen(path.c_str(), "rb");
  if (!ctx.file) fail(path, "cannot open file");
  unsigned char sig[8] = {};
  if (std::fread(sig, 1, 8, ctx.file) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
    std::fclose(ctx.file);
    fail(path, "not a PNG file (bad signature)");
  }
  std::rewind(ctx.file);
  ctx.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, on_error, on_warning);
  if (ctx.png) ctx.info = png_create_info_struct(ctx.png);
  ReadInfo ri;
  bool ok = ctx.png && ctx.info && png_read_header(&ctx, &ri);
  std::string error;
  Volume v;
  if (ok) {
    try {
      check_dimensions(path, ri.width, ri.height, 1, ri.channels);
      if (ri.bit_depth != 8 && ri.bit_depth != 16)
        fail(path, fmt::format("unsupported bit depth {}", ri.bit_depth));
      // Size check before the allocation (docs/formats.md): the rows are zlib-compressed, which never beats
      // 1032:1, so a header claiming more than that of the file's size is corrupt.
      std::error_code ec;
      const double file_bytes = double(fs::file_size(path, ec));
      if (!ec && double(ri.rowbytes + 1) * double(ri.height) > 1100.0 * file_bytes + 65536.0)
        fail(path, fmt::format("PNG image {}x{} cannot be held in a file of {} bytes (corrupt header)",
                               ri.width, ri.height, file_bytes));
      std::vector<png_byte> pixels(ri.rowbytes * ri.height);
      std::vector<png_bytep> rows(ri.height);
      for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = pixels.data() + y * ri.rowbytes;
      ok = png_read_rows(&ctx, rows.data());
      if (ok) {
        long depth = 1;
        if (as_volume && ri.depth > 1) {
          if (ri.height % ri.depth != 0)
            fail(path,
                 fmt::format("image height {} is not a multiple of {} = {}", ri.height, kDepthKey, ri.depth));
          depth = ri.depth;
        }
        v = Volume(int(ri.width), int(ri.height / depth), int(depth), ri.channels);
        const double scale = ri.bit_depth == 8 ? 1.0 / 255.0 : 1.0 / 65535.0;
        for (std::size_t y = 0; y < ri.height; ++y) {
          const png_byte* row = rows[y];
          float* dst = v.data.data() + y * std::size_t(ri.width) * ri.channels;
          for (std::size_t i = 0; i < std::size_t(ri.width) * ri.channels; ++i) {
            const unsigned q = ri.bit_depth == 8 ? row[i] : (unsigned(row[2 * i]) << 8) | row[2 * i + 1];
            dst[i] = float(q * scale);
          }
        }
      }
    } catch (const InputError& e) {
      error = e.what();
    }
  }
  png_destroy_read_struct(&ctx.png, &ctx.info, nullptr);
  std::fclose(ctx.file);
  if (!error.empty()) throw InputError(error);
  if (!ok) fail(path, fmt::format("cannot read PNG: {}", ctx.message[0] ? ctx.message : "corrupt file"));
  return v;
}

}  // namespace msh::io::codecs

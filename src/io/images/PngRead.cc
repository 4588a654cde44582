// levelfuse: the pixels of PNG files.

#include "PngRead.h"

#include "../ByteOrder.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace levelfuse::io::detail {

namespace {

/// Deflate compresses by at most 1032:1, so a PNG's pixels cannot take more
/// than that many times the file's size.
constexpr double kMaxDeflateRatio = 1032.0;

/// libpng reports errors through longjmp; the message is kept here.
struct PngErrors {
  std::jmp_buf jump;
  char message[256] = "";
};

extern "C" void onPngError(png_structp png, png_const_charp message) {
  auto* errors = static_cast<PngErrors*>(png_get_error_ptr(png));
  std::snprintf(errors->message, sizeof(errors->message), "%s", message);
  std::longjmp(errors->jump, 1);
}
extern "C" void onPngWarning(png_structp, png_const_charp) {}

/// Asks libpng for the pixels as `as` says, or writes why they cannot be.
void choosePixels(png_structp png, int depth, int colour, PngPixels as, ImageProblem& problem) {
  if (as == PngPixels::kGray16) {
    if (colour != PNG_COLOR_TYPE_GRAY)
      std::snprintf(problem, sizeof(problem),
                    "not a grayscale image (PNG colour type %d): a depth image has one channel", colour);
    else if (depth != 16)
      std::snprintf(problem, sizeof(problem), "has %d-bit samples; a depth image needs 16 bits", depth);
    if (detail::hostIsLittleEndian()) png_set_swap(png);  // PNG is big-endian
    return;
  }
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA) {
    if (depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    png_set_gray_to_rgb(png);
  }
  if (depth == 16) png_set_strip_16(png);
  png_set_strip_alpha(png);
}

}  // namespace

// Plain C inside: no destructors are skipped by libpng's longjmp.
std::string readPngPixels(const char* path, double fileBytes, PngPixels as, const ImageKind& kind,
                          const MemoryBudget& budget, int& width, int& height, std::vector<std::uint8_t>& pixels) {
  FILE* file = std::fopen(path, "rb");
  if (!file) return "cannot be opened for reading";
  unsigned char signature[8];
  if (std::fread(signature, 1, 8, file) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
    std::fclose(file);
    return "not a PNG file";
  }
  PngErrors errors;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, onPngError, onPngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    return "out of memory";
  }
  std::vector<png_bytep>* rows = new std::vector<png_bytep>();
  if (setjmp(errors.jump)) {
    png_destroy_read_struct(&png, &info, nullptr);
    std::fclose(file);
    delete rows;
    if (std::strcmp(errors.message, "Read Error") == 0) return "truncated PNG data (the file ends inside a chunk)";
    return std::string("corrupt PNG data (") + errors.message + ")";
  }
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
  // Skip, unread, every chunk an image's pixels do not need (text, colour
  // profiles, ...): libpng would allocate whatever length such a chunk declares.
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, nullptr, -1);
#if defined(FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION)
  // Fuzzer builds only: accept wrong checksums, so that mutated inputs reach
  // the decoder instead of stopping at the first CRC.
  png_set_crc_action(png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
#if defined(PNG_IGNORE_ADLER32)
  png_set_option(png, PNG_IGNORE_ADLER32, PNG_OPTION_ON);
#endif
#endif
  png_read_info(png, info);
  const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
  const int depth = png_get_bit_depth(png, info), colour = png_get_color_type(png, info);
  ImageProblem problem = "";  // no C++ object may live across libpng's longjmp
  choosePixels(png, depth, colour, as, problem);
  if (problem[0] == 0) checkImageSize(w, h, kind, budget, problem);
  if (problem[0] == 0 && double(h) * (1.0 + 2.0 * double(w)) > kMaxDeflateRatio * fileBytes)
    std::snprintf(problem, sizeof(problem),
                  "the header declares %u x %u pixels, more than the file's %.0f bytes can hold (truncated?)",
                  unsigned(w), unsigned(h), fileBytes);
  if (problem[0] == 0) {
    png_read_update_info(png, info);
    const std::size_t rowBytes = png_get_rowbytes(png, info);
    const std::size_t expected = std::size_t(w) * (as == PngPixels::kGray16 ? 2 : 3);
    if (rowBytes != expected) {
      std::snprintf(problem, sizeof(problem), "rows of %zu bytes where %zu were expected", rowBytes, expected);
    } else {
      width = static_cast<int>(w);
      height = static_cast<int>(h);
      pixels.assign(rowBytes * h, 0);
      rows->resize(h);
      for (png_uint_32 y = 0; y < h; ++y) (*rows)[y] = pixels.data() + std::size_t(y) * rowBytes;
      png_read_image(png, rows->data());
      png_read_end(png, nullptr);
    }
  }
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  delete rows;
  return std::string(problem);
}

}  // namespace levelfuse::io::detail

// levelfuse: 8-bit RGB PNG files.

#include "PngWrite.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <stdexcept>

namespace levelfuse::io::detail {

namespace {

/// libpng reports through callbacks: an error longjmps back with its message
/// kept here; warnings are kept too, for the error message, never printed.
struct PngMessages {
  std::jmp_buf jump;
  char error[256] = "";
  char warning[256] = "";
};

extern "C" void onPngWriteError(png_structp png, png_const_charp message) {
  auto* messages = static_cast<PngMessages*>(png_get_error_ptr(png));
  std::snprintf(messages->error, sizeof(messages->error), "%s", message);
  std::longjmp(messages->jump, 1);
}
extern "C" void onPngWriteWarning(png_structp png, png_const_charp message) {
  auto* messages = static_cast<PngMessages*>(png_get_error_ptr(png));
  std::snprintf(messages->warning, sizeof(messages->warning), "%s", message);
}

/// Writes the picture with libpng; returns an error message, empty on success.
/// Plain C inside: no destructors are skipped by libpng's longjmp.
std::string writeRgbPngFile(std::FILE* file, int width, int height, const std::uint8_t* rgb) {
  PngMessages messages;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &messages, onPngWriteError, onPngWriteWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    return "libpng cannot start (out of memory?)";
  }
  if (setjmp(messages.jump)) {
    png_destroy_write_struct(&png, &info);
    return std::string("libpng: ") + messages.error + (messages.warning[0] ? std::string(" (") + messages.warning + ")" : "");
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y)
    png_write_row(png, const_cast<png_bytep>(rgb + static_cast<std::size_t>(y) * width * 3));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return "";
}

}  // namespace

void writeRgbPng(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) throw std::runtime_error("cannot open a temporary file beside it");
  const std::string error = writeRgbPngFile(file, width, height, rgb.data());
  const bool flushed = std::fflush(file) == 0 && std::ferror(file) == 0;
  const bool closed = std::fclose(file) == 0;
  if (!error.empty()) throw std::runtime_error(error);
  if (!flushed || !closed) throw std::runtime_error("write error (disk full?)");
}

}  // namespace levelfuse::io::detail

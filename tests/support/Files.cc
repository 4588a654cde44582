#include "support/Files.h"

#include <png.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace levelfuse::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
  static std::atomic<int> counter{0};
  mPath = fs::temp_directory_path() /
          ("levelfuse_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(mPath);
  fs::create_directories(mPath);
}

TempDir::~TempDir() {
  std::error_code ignored;
  fs::remove_all(mPath, ignored);
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void writePng(const std::string& path, int width, int height, int bitDepth, int channels,
              const std::vector<std::uint16_t>& samples) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) throw std::runtime_error("cannot write " + path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_set_IHDR(png, info, width, height, bitDepth, channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const int bytesPerSample = bitDepth / 8;
  std::vector<unsigned char> row(static_cast<std::size_t>(width) * channels * bytesPerSample);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width * channels; ++x) {
      const std::uint16_t s = samples[static_cast<std::size_t>(y) * width * channels + x];
      if (bytesPerSample == 2) {
        row[2 * x] = static_cast<unsigned char>(s >> 8);  // PNG is big-endian
        row[2 * x + 1] = static_cast<unsigned char>(s & 0xff);
      } else {
        row[x] = static_cast<unsigned char>(s);
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(file);
}

PngImage readPng8(const std::string& path) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) throw std::runtime_error("cannot read " + path);
  image.format = PNG_FORMAT_RGB;
  PngImage out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.channels = 3;
  out.samples.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, out.samples.data(), 0, nullptr))
    throw std::runtime_error("cannot decode " + path);
  return out;
}

}  // namespace levelfuse::test

// Files for tests: a scratch directory and writers for small inputs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace levelfuse::test {

/// A fresh directory under the system's temporary folder, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string path(const std::string& name) const { return (mPath / name).string(); }
  const std::filesystem::path& root() const { return mPath; }

 private:
  std::filesystem::path mPath;
};

void writeText(const std::string& path, const std::string& text);
void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes);
/// A PNG of `bitDepth` 8 or 16 bits and `channels` 1 (gray) or 3 (RGB); samples
/// row-major, one per channel.
void writePng(const std::string& path, int width, int height, int bitDepth, int channels,
              const std::vector<std::uint16_t>& samples);

/// An 8-bit PNG read back: width, height, channels and samples, row-major.
struct PngImage {
  int width = 0, height = 0, channels = 0;
  std::vector<std::uint8_t> samples;
  const std::uint8_t* pixel(int x, int y) const {
    return &samples[(static_cast<std::size_t>(y) * width + x) * channels];
  }
};
PngImage readPng8(const std::string& path);

}  // namespace levelfuse::test

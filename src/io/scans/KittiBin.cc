// levelfuse: KITTI velodyne sweeps, float32 little-endian x y z reflectance
// per point (readKittiBin; see PointScans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/scans/PointScans.h>

#include "../ByteOrder.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

namespace levelfuse::io {

namespace {

/// Bytes of a point: four float32.
constexpr std::uintmax_t kPointBytes = 16;
/// Bytes held per point while a sweep is read and binned: its bytes, its
/// position and its share of the range map.
constexpr double kBytesPerPoint = 64.0;

/// The file's size, which must be a positive whole number of points.
std::uintmax_t sweepBytes(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path, "cannot tell the file's size (" + ec.message() + ")");
  if (bytes == 0) throw InputError(path, "no points: the file is empty");
  if (bytes % kPointBytes != 0)
    throw InputError(path, "a size of " + std::to_string(bytes) + " bytes is not a whole number of points of " +
                               std::to_string(kPointBytes) + " bytes (x y z reflectance, float32): truncated, or not "
                               "a KITTI velodyne file");
  return bytes;
}

std::vector<unsigned char> wholeFile(const std::string& path, std::uintmax_t bytes) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw InputError(path, "cannot be opened for reading");
  std::vector<unsigned char> data(static_cast<std::size_t>(bytes));
  if (std::fread(data.data(), 1, data.size(), file.get()) != data.size())
    throw InputError(path, "cannot read its " + std::to_string(bytes) + " bytes (an input/output error, or the file "
                           "shrank while it was read)");
  return data;
}

}  // namespace

PointCloud readKittiBin(const std::string& path, const MemoryBudget& budget) {
  requireInputFile(path);
  const std::uintmax_t bytes = sweepBytes(path);
  const std::uintmax_t count = bytes / kPointBytes;
  requireMemory(budget, path, static_cast<double>(count) * kBytesPerPoint, std::to_string(count) + " points",
                "split the sweep, or use a machine with more memory");
  const std::vector<unsigned char> data = wholeFile(path, bytes);
  PointCloud cloud;
  cloud.points.reserve(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned char* point = data.data() + i * kPointBytes;
    float values[4];
    for (int k = 0; k < 4; ++k) values[k] = detail::littleEndianFloat(point + 4 * k);
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(values[k]))
        throw InputError(path, "point " + std::to_string(i) + " (at byte " + std::to_string(i * kPointBytes) +
                                   ") has " + (k < 3 ? "a coordinate" : "a reflectance") + " that is not finite");
    cloud.points.emplace_back(values[0], values[1], values[2]);
  }
  return cloud;
}

}  // namespace levelfuse::io

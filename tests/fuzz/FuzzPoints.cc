// Fuzzes the point-cloud readers: the input's first byte picks the reader,
// the rest is the file: 'x' XYZ text, 'p' PLY (each read and binned into a
// spherical range map with the angular steps estimated from its points:
// rangeMapFromPointCloud), 'k' a KITTI velodyne sweep (read by its lasers if
// they are listed in firing order, else binned: rangeMapsOfSweep), 'c' a KITTI calib.txt,
// 'o' a KITTI poses file (its frame 1); any other byte picks one of them by
// its value.

#include "FuzzInput.h"

#include <levelfuse/io/scans/PointScans.h>

namespace {

using namespace levelfuse;

constexpr char kReaders[] = {'x', 'p', 'k', 'c', 'o'};

char readerOf(std::uint8_t first) {
  for (const char reader : kReaders)
    if (first == static_cast<std::uint8_t>(reader)) return reader;
  return kReaders[first % sizeof(kReaders)];
}

void binned(const std::string& path, const io::PointCloud& cloud) {
  io::rangeMapFromPointCloud(cloud.points, openvdb::math::Mat4d::identity(), std::nullopt, 0.01, path, "fuzz");
}

/// A KITTI sweep as the manifest reads it: by its lasers if it lists them in firing order.
void swept(const std::string& path, const io::PointCloud& cloud) {
  io::rangeMapsOfSweep(cloud.points, openvdb::math::Mat4d::identity(), std::nullopt, 0.01, path, "fuzz");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const char reader = readerOf(data[0]);
  const char* const names[] = {"input.xyz", "input.ply", "input.bin", "calib.txt", "poses.txt"};
  const std::string path = fuzz::writeScratchFile(
      names[std::string(kReaders, sizeof(kReaders)).find(reader)], data + 1, size - 1);
  fuzz::expectOnlyInputErrors([&] {
    switch (reader) {
      case 'x': binned(path, io::readXyzPoints(path)); break;
      case 'p': binned(path, io::readPlyPoints(path)); break;
      case 'k': swept(path, io::readKittiBin(path)); break;
      case 'c': io::readKittiVelodyneToCamera(path); break;
      default: io::readKittiCameraToWorld(path, 1); break;
    }
  });
  return 0;
}

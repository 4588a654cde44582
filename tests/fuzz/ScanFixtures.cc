// libFuzzer targets: valid files for fuzzed inputs to refer to.

#include "ScanFixtures.h"

#include "FuzzInput.h"
#include "support/Files.h"

#include <openvdb/Types.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <vector>

namespace levelfuse::fuzz {

std::string rangeGridPly() {
  std::string ply =
      "ply\nformat ascii 1.0\nobj_info num_cols 3\nobj_info num_rows 3\nelement vertex 9\n"
      "property float x\nproperty float y\nproperty float z\nelement range_grid 9\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) ply += std::to_string(0.001 * c) + " " + std::to_string(0.001 * r) + " 0\n";
  for (int i = 0; i < 9; ++i) ply += "1 " + std::to_string(i) + "\n";
  return ply;
}

std::string sphericalScanPtx() {
  std::string ptx = "3\n3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  const double step = 2.0 * M_PI / 128.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      const double azimuth = step * c, elevation = step * r;
      ptx += std::to_string(2.0 * std::cos(elevation) * std::cos(azimuth)) + " " +
             std::to_string(2.0 * std::cos(elevation) * std::sin(azimuth)) + " " +
             std::to_string(2.0 * std::sin(elevation)) + " 0.5\n";
    }
  return ptx;
}

/// The directions of sphericalScanPtx()'s 3 x 3 points, and more rows and
/// columns so that their steps can be estimated, 2 m from the scanner.
std::vector<openvdb::Vec3d> sphericalScanPoints() {
  std::vector<openvdb::Vec3d> points;
  const double step = 2.0 * M_PI / 128.0;
  for (int c = 0; c < 6; ++c)
    for (int r = 0; r < 4; ++r)
      points.push_back(openvdb::Vec3d(std::cos(step * r) * std::cos(step * c), std::cos(step * r) * std::sin(step * c),
                                      std::sin(step * r)) * 2.0);
  return points;
}

std::string sphericalScanXyz() {
  std::string xyz;
  for (const openvdb::Vec3d& p : sphericalScanPoints())
    xyz += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  return xyz;
}

std::string sphericalScanKittiBin() {
  std::string bin;
  for (const openvdb::Vec3d& p : sphericalScanPoints()) {
    const float values[4] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), 0.5f};
    bin.append(reinterpret_cast<const char*>(values), sizeof values);  // little-endian machines
  }
  return bin;
}

void writeScanFixtures() {
  const std::filesystem::path folder(scratchFolder());
  writeScratchFile("scan.ply", rangeGridPly());
  writeScratchFile("scan.conf", "camera 0 0 0 0 0 0 1\nbmesh scan.ply 0 0 0.01 0 0 0 1\n");
  test::writePng((folder / "depth.png").string(), 4, 4, 16, 1, std::vector<std::uint16_t>(16, 1500));
  test::writePng((folder / "tiny.png").string(), 1, 1, 16, 1, {1500});
  std::string pfm = "Pf\n4 4\n-1.0\n";
  const float metres = 1.5f;
  for (int i = 0; i < 16; ++i) pfm.append(reinterpret_cast<const char*>(&metres), sizeof metres);
  writeScratchFile("depth.pfm", pfm);
  writeScratchFile("k.txt", "10 0 2\n0 10 2\n0 0 1\n");
  writeScratchFile("pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  writeScratchFile("scan.ptx", sphericalScanPtx());
  writeScratchFile("points.xyz", sphericalScanXyz());
  writeScratchFile("velodyne.bin", sphericalScanKittiBin());
  writeScratchFile("calib.txt", "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n");
  writeScratchFile("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0.5 0 1 0 0 0 0 1 0\n");
}

}  // namespace levelfuse::fuzz

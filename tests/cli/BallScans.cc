// The converter's tests' ball.

#include "BallScans.h"

#include <levelfuse/io/Ply.h>

#include <algorithm>
#include <cmath>

namespace levelfuse::test {

using openvdb::Vec3d;

PtxGrid ballScannerGrid(int k) {
  const double around = k * M_PI / 4.0, up = (k % 2 == 0 ? 1.0 : -1.0) * M_PI / 4.0;
  const Vec3d position = Vec3d(std::cos(around), std::sin(around), std::tan(up)) * kScannerDistance * std::cos(up);
  PtxGrid grid;
  grid.columns = grid.rows = 51;
  grid.azimuthStart = -0.3;
  grid.elevationStart = -up - 0.3;
  grid.azimuthStep = grid.elevationStep = 2.0 * M_PI / 512.0;
  grid.scannerToWorld = scannerLookingAt(position, Vec3d(0.0));
  return grid;
}

std::vector<Vec3d> ballScanPoints(const PtxGrid& grid) {
  const Vec3d ballFromScanner = grid.scannerToWorld.inverse().transform(Vec3d(0.0));
  return scanPoints(grid, sphere(ballFromScanner, kBallRadius));
}

void expectBallInfo(const nlohmann::json& info, double tolerance) {
  ASSERT_EQ(info["scans"].size(), static_cast<std::size_t>(kBallScanners));
  EXPECT_EQ(info["scans"][0]["projection"], "spherical");
  EXPECT_DOUBLE_EQ(info["scans"][0]["sigma"].get<double>(), 0.002);
  EXPECT_NEAR(info["scans"][2]["scanner_position"][1].get<double>(), kScannerDistance * std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(info["scans"][2]["scanner_position"][2].get<double>(), kScannerDistance * std::sqrt(0.5), 1e-6);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(info["bounds"][0][axis].get<double>(), -kBallRadius - tolerance);
    EXPECT_LT(info["bounds"][1][axis].get<double>(), kBallRadius + tolerance);
  }
}

void expectBallReconstruction(const CliRun& run, const std::string& meshPath) {
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = jsonOf(run);
  EXPECT_EQ(j["scans"], kBallScanners);
  EXPECT_LT(j["fit"]["rms"].get<double>(), 0.01);  // half a voxel
  const io::PlyData mesh = io::readPly(meshPath);
  const io::PlyElement* vertices = mesh.element("vertex");
  ASSERT_TRUE(vertices);
  ASSERT_GT(vertices->count, 1000u);
  double sum = 0.0, farthest = 0.0;
  for (std::size_t i = 0; i < vertices->count; ++i) {
    const double radius = Vec3d(vertices->values[0][i], vertices->values[1][i], vertices->values[2][i]).length();
    sum += radius;
    farthest = std::max(farthest, std::fabs(radius - kBallRadius));
  }
  EXPECT_NEAR(sum / static_cast<double>(vertices->count), kBallRadius, 0.005);
  EXPECT_LT(farthest, 0.05);  // two and a half voxels: the rims of the unseen parts left out
}

}  // namespace levelfuse::test

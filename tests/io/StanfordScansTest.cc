// Stanford .conf files and range-grid scans, synthetic and real.

#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/TestSupport.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/StanfordScans.h>

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace levelfuse::io {
namespace {

using test::expectInputError;
using test::TempDir;
using test::writeText;

/// A range-grid PLY of `rows` x `cols` samples of the plane z = 0.1 x + 0.01
/// (metres, spacing 1 mm), with the listed cells left empty.
std::string planeScan(int rows, int cols, const std::vector<int>& empty = {}) {
  std::ostringstream points, grid;
  int n = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int g = r * cols + c;
      if (std::find(empty.begin(), empty.end(), g) != empty.end()) {
        grid << "0\n";
        continue;
      }
      const double x = 0.001 * c, y = 0.001 * r;
      points << x << ' ' << y << ' ' << 0.1 * x + 0.01 << '\n';
      grid << "1 " << n++ << '\n';
    }
  std::ostringstream ply;
  ply << "ply\nformat ascii 1.0\nobj_info num_cols " << cols << "\nobj_info num_rows " << rows
      << "\nelement vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\nelement range_grid "
      << rows * cols << "\nproperty list uchar int vertex_indices\nend_header\n"
      << points.str() << grid.str();
  return ply.str();
}


TEST(StanfordConf, PlacesScansByTheConjugateRotation) {
  TempDir dir;
  writeText(dir.path("a.ply"), planeScan(4, 4));
  // 90 degrees about z: R maps x to y, so R^T maps x to -y.
  const double s = std::sqrt(0.5);
  writeText(dir.path("scans.conf"), "camera 0 0 0 0 0 0 1\nmesh cylinder 0 0 0 0 0 0 1\n\nbmesh a.ply 1 2 3 0 0 " +
                                        std::to_string(s) + " " + std::to_string(s) + "\n");
  const auto scans = readStanfordConf(dir.path("scans.conf"));
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_EQ(scans[0].file, "a.ply");
  EXPECT_EQ(scans[0].line, 4);
  const openvdb::Vec3d p = scans[0].scanToWorld().transform(openvdb::Vec3d(1, 0, 0));
  EXPECT_NEAR(p.x(), 1.0, 1e-6);
  EXPECT_NEAR(p.y(), 2.0 - 1.0, 1e-6);
  EXPECT_NEAR(p.z(), 3.0, 1e-6);
}

TEST(StanfordConf, RejectsBadLines) {
  TempDir dir;
  writeText(dir.path("a.ply"), planeScan(4, 4));
  const auto conf = [&](const std::string& text) {
    writeText(dir.path("s.conf"), text);
    return dir.path("s.conf");
  };
  const auto read = [&](const std::string& path) { return [path] { readStanfordConf(path); }; };
  std::string p = conf("bmesh a.ply 0 0 0 0 0 0 2\n");
  expectInputError(read(p), p, "line 1: the quaternion has norm 2");
  p = conf("bmesh a.ply 0 0 0 0 0 0 0\n");
  expectInputError(read(p), p, "the quaternion is zero");
  p = conf("camera 0 0 0 0 0 0 1\nbmesh missing.ply 0 0 0 0 0 0 1\n");
  expectInputError(read(p), p, "line 2: scan file 'missing.ply' does not exist");
  p = conf("bmesh a.ply 0 0 0 0 0 1\n");
  expectInputError(read(p), p, "expected 'bmesh FILE tx ty tz qi qj qk qr'");
  p = conf("bmesh a.ply 0 nan 0 0 0 0 1\n");
  expectInputError(read(p), p, "'nan' is not a finite number");
  p = conf("bmesh a.ply 0 1,5 0 0 0 0 1\n");
  expectInputError(read(p), p, "'1,5' is not a number");
  p = conf("scan a.ply 0 0 0 0 0 0 1\n");
  expectInputError(read(p), p, "unknown entry 'scan'");
  p = conf("camera 0 0 0 0 0 0 1\n");
  expectInputError(read(p), p, "no 'bmesh' lines");
  expectInputError(read(dir.path("none.conf")), dir.path("none.conf"), "no such file");
}

TEST(RangeGridPly, RejectsInconsistentGrids) {
  TempDir dir;
  const auto ply = [&](const std::string& text) {
    writeText(dir.path("g.ply"), text);
    return dir.path("g.ply");
  };
  const auto read = [&](const std::string& path) { return [path] { readRangeGridPly(path); }; };
  std::string good = planeScan(2, 2);
  std::string p = ply(std::string(good).replace(good.find("1 3\n"), 4, "1 9\n"));
  expectInputError(read(p), p, "range_grid entry 3 (row 1, column 1) points at vertex 9, but there are 4");
  p = ply(std::string(good).replace(good.find("num_rows 2"), 10, "num_rows 3"));
  expectInputError(read(p), p, "range_grid has 4 entries, but num_rows x num_cols = 3 x 2 = 6");
  p = ply(std::string(good).replace(good.find("obj_info num_cols 2\n"), 20, ""));
  expectInputError(read(p), p, "'obj_info num_cols' is missing");
  p = ply(std::string(good).replace(good.find("0.01\n"), 5, "nan\n"));
  expectInputError(read(p), p, "vertex 0 has a coordinate that is not finite");
  p = ply(std::string(good).replace(good.find("1 0\n"), 4, "2 0 1\n"));
  expectInputError(read(p), p, "lists 2 vertices");
}

TEST(RangeGridPly, BecomesARangeMapOfTheSameSurface) {
  TempDir dir;
  writeText(dir.path("p.ply"), planeScan(30, 40, {5, 6, 45}));
  const RangeGridScan scan = readRangeGridPly(dir.path("p.ply"));
  EXPECT_EQ(scan.points.size(), 30u * 40u - 3u);
  EXPECT_NEAR(rangeGridSpacing(scan), 0.001, 1e-4);
  openvdb::math::Mat4d pose = openvdb::math::Mat4d::identity();
  pose.setTranslation(openvdb::Vec3d(0.5, 0.0, 0.0));
  const RangeMap map = rangeMapFromScan(scan, pose, StanfordScanOptions{}, "plane");
  EXPECT_GT(map.validCount(), 1000u);
  // Points of the plane, seen from +z, are on the measured surface: D = 0.
  RangeSample s;
  for (const openvdb::Vec3d local : {openvdb::Vec3d(0.0105, 0.0133, 0.0), openvdb::Vec3d(0.03, 0.02, 0.0)}) {
    const openvdb::Vec3d onPlane(local.x(), local.y(), 0.1 * local.x() + 0.01);
    ASSERT_TRUE(map.sample(onPlane + openvdb::Vec3d(0.5, 0, 0), s));
    EXPECT_NEAR(s.D, 0.0, 1e-6);
    EXPECT_NEAR(s.lineOfSight.z(), -1.0, 1e-9);  // away from a scanner on the +z side
    // 1 mm below the plane is 1 mm behind the reading (along -z).
    ASSERT_TRUE(map.sample(onPlane + openvdb::Vec3d(0.5, 0.0, -0.001), s));
    EXPECT_NEAR(s.D, 0.001, 1e-6);
  }
}

// ---- the real scans (../shared/data) ----

struct RealSet {
  const char* conf;
  std::size_t scans, points;
  openvdb::Vec3d toward;
};

std::vector<RangeGridScan> loadRaw(const RealSet& set, std::vector<openvdb::math::Mat4d>& poses) {
  std::vector<RangeGridScan> scans;
  for (const StanfordPlacement& p : readStanfordConf(test::sharedData(set.conf))) {
    scans.push_back(readRangeGridPly(p.path));
    poses.push_back(p.scanToWorld());
  }
  return scans;
}

class RealScans : public ::testing::TestWithParam<RealSet> {};

TEST_P(RealScans, LoadWithTheRightCountsAndRegister) {
  if (test::sharedData("").empty()) GTEST_SKIP() << "../shared/data is absent: the real scans are not tested";
  const RealSet& set = GetParam();
  std::vector<openvdb::math::Mat4d> poses;
  const std::vector<RangeGridScan> scans = loadRaw(set, poses);
  ASSERT_EQ(scans.size(), set.scans);
  std::size_t points = 0;
  for (const auto& s : scans) points += s.points.size();
  EXPECT_EQ(points, set.points);

  StanfordScanOptions options;
  options.towardScanner = set.toward;
  const auto maps = loadStanfordScans(test::sharedData(set.conf), options);
  ASSERT_EQ(maps.size(), set.scans);
  for (const auto& m : maps) EXPECT_GT(m.validCount(), 10000u) << m.name();

  // Registration: each scan's points lie close to the other scans' surfaces.
  const double voxel = 0.00025, band = 0.002;
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel);
  std::vector<openvdb::FloatGrid::Ptr> distance;
  std::vector<std::vector<openvdb::Vec3d>> world(scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    std::vector<openvdb::Vec3s> vertices;
    for (const auto& p : scans[i].points) {
      world[i].push_back(poses[i].transform(p));
      vertices.emplace_back(world[i].back());  // meshToVolume takes world-space points
    }
    const auto triangles = triangulateRangeGrid(scans[i], 4.0 * rangeGridSpacing(scans[i]));
    distance.push_back(openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
        *xform, vertices, triangles, std::vector<openvdb::Vec4I>(), float(band / voxel)));
  }
  for (std::size_t i = 0; i < scans.size(); ++i) {
    std::vector<double> d;
    for (const openvdb::Vec3d& p : world[i]) {
      double nearest = band;
      for (std::size_t j = 0; j < scans.size(); ++j) {
        if (j == i) continue;
        const openvdb::Vec3d ijk = xform->worldToIndex(p);
        nearest = std::min(nearest, double(openvdb::tools::BoxSampler::sample(distance[j]->tree(), ijk)));
      }
      d.push_back(nearest);
    }
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    EXPECT_LT(d[d.size() / 2], 0.0005) << maps[i].name();
    RecordProperty("median_mm_" + std::to_string(i), std::to_string(1000 * d[d.size() / 2]));
  }
}

INSTANTIATE_TEST_SUITE_P(Stanford, RealScans,
                         ::testing::Values(RealSet{"stanford/bunny/bun.conf", 10, 362272, openvdb::Vec3d(0, 0, 1)},
                                           RealSet{"stanford/dragon/dragonStandRight.conf", 15, 469193,
                                                   openvdb::Vec3d(0.46, 0.04, 0.89)}),
                         [](const auto& param) { return param.index == 0 ? std::string("Bunny") : std::string("Dragon"); });

}  // namespace
}  // namespace levelfuse::io

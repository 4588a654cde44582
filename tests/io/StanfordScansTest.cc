// Stanford .conf files and range-grid scans, synthetic and real.

#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/TestSupport.h"
#include "support/WantedScans.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/StanfordScans.h>

#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

namespace levelfuse::io {
namespace {

using test::expectInputError;
using test::TempDir;
namespace fs = std::filesystem;
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
  // Pixels of half the 1 mm sample spacing; the ray density and the samples are the scan's.
  EXPECT_NEAR(map.orthographicProjection().pixelSize, 0.0005, 1e-5);
  EXPECT_NEAR(map.maxRaySpacing(), 0.001, 1e-5);
  ASSERT_EQ(map.samples().size(), scan.points.size());
  EXPECT_NEAR((map.samples()[7] - pose.transform(scan.points[7])).length(), 0.0, 1e-12);
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

TEST(RangeGridPly, EverySampleIsAReadingOfItsMapBoundaryIncluded) {
  // A plane with a hole: the samples on the grid's border and around the hole
  // lie on the edge of the triangulated area, where pixel centres alone leave
  // them outside every cell of four readings.
  TempDir dir;
  std::vector<int> hole;
  for (int r = 8; r < 12; ++r)
    for (int c = 10; c < 15; ++c) hole.push_back(r * 25 + c);
  writeText(dir.path("p.ply"), planeScan(20, 25, hole));
  const RangeGridScan scan = readRangeGridPly(dir.path("p.ply"));
  const auto sampled = [&](const StanfordScanOptions& options) {
    const RangeMap map = rangeMapFromScan(scan, openvdb::math::Mat4d::identity(), options, "plane");
    std::size_t count = 0;
    for (const openvdb::Vec3d& p : scan.points) {
      RangeSample s;
      if (!map.sample(p, s)) continue;
      EXPECT_NEAR(s.D, 0.0, 1e-6) << p;  // a plane extrapolates exactly
      ++count;
    }
    return count;
  };
  EXPECT_EQ(sampled(StanfordScanOptions{}), scan.points.size());
  StanfordScanOptions withoutExtension;
  withoutExtension.edgeExtension = 0.0;
  EXPECT_LT(sampled(withoutExtension), scan.points.size() - 40);  // the far borders and the hole's rim are lost
  StanfordScanOptions bad;
  bad.edgeExtension = -1.0;
  expectInputError([&] { rangeMapFromScan(scan, openvdb::math::Mat4d::identity(), bad, "plane"); }, scan.path,
                   "the edge extension must be 0 to 8 pixels");
}

TEST(RangeGridPly, NoiseIsEstimatedFromTheScan) {
  // The plane z = 0.1 x + 0.01 with Gaussian noise of 0.05 mm along z (the
  // line of sight), on a grid with a hole and a depth step that must not count.
  const int rows = 60, cols = 70;
  const double sigma = 0.00005;
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, sigma);
  RangeGridScan scan;
  scan.rows = rows;
  scan.cols = cols;
  scan.grid.assign(rows * cols, -1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (r > 20 && r < 25 && c > 30 && c < 40) continue;  // a dropout
      const double x = 0.001 * c, y = 0.001 * r;
      const double step = c >= 50 ? 0.004 : 0.0;  // a depth discontinuity
      scan.grid[r * cols + c] = static_cast<int>(scan.points.size());
      scan.points.emplace_back(x, y, 0.1 * x + 0.01 + step + noise(random));
    }
  EXPECT_NEAR(estimateRangeNoise(scan, openvdb::Vec3d(0, 0, 1)), sigma, 0.1 * sigma);
  // The map takes the estimate unless told a sigma.
  EXPECT_NEAR(rangeMapFromScan(scan, openvdb::math::Mat4d::identity(), {}, "noisy").sigma(), sigma, 0.1 * sigma);
  StanfordScanOptions told;
  told.sigma = 0.0003;
  EXPECT_EQ(rangeMapFromScan(scan, openvdb::math::Mat4d::identity(), told, "noisy").sigma(), 0.0003);
  // A noiseless plane: a hundredth of the 1 mm spacing; a scan too small to
  // tell (3 x 3 samples, one full neighbourhood): a quarter of it.
  TempDir dir;
  writeText(dir.path("p.ply"), planeScan(20, 20));
  const RangeGridScan plane = readRangeGridPly(dir.path("p.ply"));
  EXPECT_LT(estimateRangeNoise(plane, openvdb::Vec3d(0, 0, 1)), 1e-7);
  EXPECT_NEAR(rangeMapFromScan(plane, openvdb::math::Mat4d::identity(), {}, "plane").sigma(), 0.00001, 1e-6);
  writeText(dir.path("small.ply"), planeScan(3, 3));
  const RangeGridScan small = readRangeGridPly(dir.path("small.ply"));
  EXPECT_EQ(estimateRangeNoise(small, openvdb::Vec3d(0, 0, 1)), 0.0);
  EXPECT_NEAR(rangeMapFromScan(small, openvdb::math::Mat4d::identity(), {}, "small").sigma(), 0.00025, 1e-5);
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

TEST(StanfordConf, AScanNotWantedIsNotRead) {
  // The bunny's .conf with its third scan no PLY at all: it is not wanted, so it is never read.
  if (test::sharedData("").empty()) GTEST_SKIP() << "../shared/data is absent: the real scans are not tested";
  TempDir dir;
  const fs::path bunny = fs::path(test::sharedData("stanford/bunny/bun.conf")).parent_path();
  fs::copy(bunny, dir.path("bunny"), fs::copy_options::recursive);
  const std::vector<StanfordPlacement> placements = readStanfordConf(dir.path("bunny/bun.conf"));
  ASSERT_GE(placements.size(), 3u);
  test::writeText(placements[2].path, "not a PLY file");
  ScanLoadOptions options;
  std::vector<std::size_t> asked;
  options.wanted = test::everyScanBut(2, asked);
  const std::vector<RangeMap> maps = loadScans(dir.path("bunny/bun.conf"), options);
  ASSERT_EQ(maps.size(), placements.size() - 1);
  EXPECT_EQ(maps[2].name(), placements[3].file);
  EXPECT_EQ(asked.size(), placements.size());
  options.wanted = {};
  EXPECT_THROW(loadScans(dir.path("bunny/bun.conf"), options), InputError) << "the third scan is read now";
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
  for (const auto& m : maps) {
    EXPECT_GT(m.validCount(), 10000u) << m.name();
    // The noise estimated from each scan: the Cyberware's 0.05 to 0.09 mm.
    EXPECT_GT(m.sigma(), 0.00004) << m.name();
    EXPECT_LT(m.sigma(), 0.0001) << m.name();
  }
  // Each scan's map reads its own points, those on its boundary included:
  // at least 96% within 0.5 mm (about 90% of the bunny's were while the
  // maps stopped at the pixel centres inside the scans' triangles).
  for (std::size_t i = 0; i < maps.size(); ++i) {
    std::size_t read = 0;
    for (const openvdb::Vec3d& p : scans[i].points) {
      RangeSample s;
      read += maps[i].sample(poses[i].transform(p), s) && std::fabs(s.D) < 0.0005;
    }
    const double fraction = static_cast<double>(read) / static_cast<double>(scans[i].points.size());
    EXPECT_GT(fraction, 0.96) << maps[i].name();
    RecordProperty("own_points_read_" + std::to_string(i), std::to_string(fraction));
  }

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
  // Each grid is read through an accessor, which remembers the nodes it last
  // visited: a scan's points are read in the order they were scanned.
  std::vector<openvdb::FloatGrid::ConstAccessor> accessors;
  for (const openvdb::FloatGrid::Ptr& grid : distance) accessors.push_back(grid->getConstAccessor());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    std::vector<double> d;
    for (const openvdb::Vec3d& p : world[i]) {
      double nearest = band;
      const openvdb::Vec3d ijk = xform->worldToIndex(p);
      for (std::size_t j = 0; j < scans.size(); ++j) {
        if (j == i) continue;
        nearest = std::min(nearest, double(openvdb::tools::BoxSampler::sample(accessors[j], ijk)));
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

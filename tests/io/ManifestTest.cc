// JSON scan manifests.

#include "support/Files.h"
#include "support/TestSupport.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace levelfuse::io {
namespace {

using test::TempDir;
using test::writeText;

void expectManifestError(const std::string& path, const std::string& fragment) {
  try {
    loadManifest(path);
    ADD_FAILURE() << "no error (expected '" << fragment << "')";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Manifest, DescribesDepthCamerasWithoutCode) {
  TempDir dir;
  std::vector<std::uint16_t> depth(8 * 6, 1500);
  depth[0] = 0;
  test::writePng(dir.path("d.png"), 8, 6, 16, 1, depth);
  writeText(dir.path("k.txt"), "10 0 3.5\n0 10 2.5\n0 0 1\n");
  writeText(dir.path("m.json"), R"({
    "scans": [
      { "format": "depth-png", "file": "d.png", "depth_scale": 0.001,
        "intrinsics_file": "k.txt", "pose": [1,0,0,0.5, 0,1,0,0, 0,0,1,0, 0,0,0,1] },
      { "format": "depth-png", "file": "d.png", "depth_scale": 0.002,
        "intrinsics": { "fx": 10, "fy": 10, "cx": 3.5, "cy": 2.5 },
        "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "sigma": 0.004 }
    ] })");
  const auto maps = loadManifest(dir.path("m.json"));
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].validCount(), 47u);
  // The centre pixel's reading, 1.5 m straight ahead of a camera moved by 0.5 m in x.
  const openvdb::Vec3d p = maps[0].readingPoint(3, 2);
  EXPECT_NEAR(p.z(), 1.5, 1e-6);
  EXPECT_NEAR(p.x(), 0.5 + (3 - 3.5) / 10.0 * 1.5, 1e-6);
  EXPECT_NEAR(maps[1].readingPoint(3, 2).z(), 3.0, 1e-6);
  RangeSample s;
  ASSERT_TRUE(maps[1].sample(openvdb::Vec3d(0.0, 0.0, 2.9), s));
  EXPECT_NEAR(s.sigma, 0.004, 1e-9);
}

TEST(Manifest, NamesTheEntryAtFault) {
  TempDir dir;
  const auto manifest = [&](const std::string& text) {
    writeText(dir.path("m.json"), text);
    return dir.path("m.json");
  };
  expectManifestError(manifest("{ \"scans\": [ "), "not valid JSON");
  expectManifestError(manifest("[1, 2]"), "an array 'scans'");
  expectManifestError(manifest("{ \"scans\": [] }"), "'scans' is empty");
  expectManifestError(manifest(R"({ "scans": [ { "file": "x.png" } ] })"), "scans[0]: missing 'format'");
  expectManifestError(manifest(R"({ "scans": [ { "format": "lidar", "file": "x" } ] })"),
                      "scans[0]: unknown format 'lidar'");
  expectManifestError(
      manifest(R"({ "scans": [ { "format": "depth-png", "file": "d.png", "intrinsics_file": "k.txt", "pose": [1, 2] } ] })"),
      "no such file");
  test::writePng(dir.path("d.png"), 4, 4, 16, 1, std::vector<std::uint16_t>(16, 1000));
  writeText(dir.path("k.txt"), "10 0 2\n0 10 2\n0 0 1\n");
  expectManifestError(
      manifest(R"({ "scans": [ { "format": "depth-png", "file": "d.png", "intrinsics_file": "k.txt", "pose": [1, 2] } ] })"),
      "scans[0]: 'pose' needs 16 numbers");
  expectManifestError(manifest(R"({ "scans": [ { "format": "stanford-ply", "file": "a.ply",
                                   "translation": [0, 0, 0], "quaternion": [0, 0, 0, 0] } ] })"),
                      "scans[0]: 'quaternion' has norm 0");
  expectManifestError(manifest(R"({ "scans": [ { "format": "depth-png", "file": "d.png", "depth_scale": -1,
                                   "intrinsics_file": "k.txt", "pose_file": "k.txt" } ] })"),
                      "'depth_scale' must be positive");
}

TEST(Manifest, WritesAndReadsSphericalScans) {
  // The synthetic room's tripods, their noise growing with range, and its truth.
  synth::SceneOptions options;
  options.resolution = 20;
  options.noise = 0.0004;
  const synth::Scene scene = synth::roomScene(shapes::Room{}, options);
  TempDir dir;
  const std::string manifest = writeScanSet(dir.path("room"), scene.maps, scene.truth);
  const std::vector<RangeMap> maps = loadManifest(manifest);
  ASSERT_EQ(maps.size(), scene.maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const RangeMap &a = scene.maps[i], &b = maps[i];
    ASSERT_EQ(b.kind(), RangeMap::Kind::kSpherical);
    ASSERT_EQ(b.width(), a.width());
    ASSERT_EQ(b.height(), a.height());
    EXPECT_NEAR(b.sphericalProjection().azimuthStart, a.sphericalProjection().azimuthStart, 1e-12);
    EXPECT_NEAR(b.sphericalProjection().azimuthStep, a.sphericalProjection().azimuthStep, 1e-12);
    EXPECT_NEAR(b.sphericalProjection().elevationStart, a.sphericalProjection().elevationStart, 1e-12);
    EXPECT_NEAR(b.sphericalProjection().elevationStep, a.sphericalProjection().elevationStep, 1e-12);
    EXPECT_TRUE(b.mapToWorld().eq(a.mapToWorld(), 1e-12));
    ASSERT_NE(b.depthNoise(), nullptr);
    EXPECT_DOUBLE_EQ(b.depthNoise()->perMetre, a.depthNoise()->perMetre);
    EXPECT_DOUBLE_EQ(b.depthNoise()->minimum, a.depthNoise()->minimum);
    EXPECT_EQ(b.validCount(), a.validCount());
    for (int v = 0; v < a.height(); ++v)
      for (int u = 0; u < a.width(); ++u) ASSERT_EQ(b.reading(u, v), a.reading(u, v)) << u << " " << v;
  }
  const std::optional<shapes::AnalyticShape> truth = loadManifestTruth(manifest);
  ASSERT_TRUE(truth);
  EXPECT_STREQ(truth->name(), "room");
  EXPECT_EQ(truth->room.size, shapes::Room{}.size);
}

TEST(Manifest, WritesAndReadsUnevenRows) {
  // A LiDAR's rows spaced unevenly go out as 'row_elevations' and come back as they were.
  constexpr double kDegree = M_PI / 180.0;
  SphericalProjection grid;
  grid.azimuthStart = -20.0 * kDegree;
  grid.azimuthStep = 0.5 * kDegree;
  grid.rowElevations = {-24.0 * kDegree, -23.5 * kDegree, -23.0 * kDegree, -21.5 * kDegree, 2.0 * kDegree};
  const RangeMap map = RangeMap::spherical(81, 5, std::vector<float>(81 * 5, 7.5f), grid,
                                           openvdb::math::Mat4d::identity(), 0.002, "sweep");
  TempDir dir;
  const std::string manifest = writeScanSet(dir.path("sweep"), {map});
  const nlohmann::json written = nlohmann::json::parse(std::ifstream(manifest));
  ASSERT_TRUE(written["scans"][0].contains("row_elevations"));
  EXPECT_FALSE(written["scans"][0].contains("elevation_step"));
  const std::vector<RangeMap> maps = loadManifest(manifest);
  ASSERT_EQ(maps.size(), 1u);
  const std::vector<double>& rows = maps[0].sphericalProjection().rowElevations;
  ASSERT_EQ(rows.size(), 5u);
  for (std::size_t r = 0; r < rows.size(); ++r) EXPECT_NEAR(rows[r], grid.rowElevations[r], 1e-12) << r;
  EXPECT_NEAR(maps[0].sphericalProjection().elevationStart, -24.0 * kDegree, 1e-12);
}

TEST(Manifest, WritesAndReadsColoursBesideEachScan) {
  // Painted views of each kind: each gets a colour image beside its range image.
  synth::SceneOptions options;
  options.resolution = 24;
  std::vector<RangeMap> maps;
  for (RangeMap::Kind kind : {RangeMap::Kind::kOrthographic, RangeMap::Kind::kPinhole, RangeMap::Kind::kSpherical}) {
    options.scanner = kind;
    synth::Scene scene = synth::analyticScene(synth::standardShape(shapes::AnalyticShape::Kind::kSphere), options);
    maps.push_back(std::move(scene.maps.front()));
  }
  for (RangeMap& m : maps)
    synth::paintReadings(m, [](const openvdb::Vec3d& x) {
      return Rgb8{static_cast<std::uint8_t>(100 + 100 * x.x()), static_cast<std::uint8_t>(100 + 100 * x.y()), 7};
    });
  maps.push_back(maps.front());  // and one without
  maps.back().setColours({});
  TempDir dir;
  const std::vector<RangeMap> read = loadManifest(writeScanSet(dir.path("painted"), maps));
  ASSERT_EQ(read.size(), maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) EXPECT_EQ(read[i].colours(), maps[i].colours()) << i;
  EXPECT_TRUE(std::filesystem::exists(dir.path("painted/scan0.colour.png")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("painted/scan3.colour.png")));
}

TEST(Manifest, RefusesAFileTooLargeToBeOne) {
  TempDir dir;
  writeText(dir.path("m.json"), "{ \"scans\": [");
  std::filesystem::resize_file(dir.path("m.json"), std::uintmax_t(65) << 20);  // sparse: no disk used
  expectManifestError(dir.path("m.json"), "a manifest of 65 MiB: manifests list scans and take a few KiB");
}

TEST(Manifest, EstimatesTheNoiseOfStanfordScansWithoutASigma) {
  // A 30 x 30 range grid of a plane with noise of 0.05 mm along z, 1 mm apart.
  TempDir dir;
  std::mt19937 random(11);
  std::normal_distribution<double> noise(0.0, 0.00005);
  std::ostringstream points, grid;
  const int rows = 30, cols = 30;
  for (int g = 0; g < rows * cols; ++g) {
    points << 0.001 * (g % cols) << ' ' << 0.001 * (g / cols) << ' ' << 0.01 + noise(random) << '\n';
    grid << "1 " << g << '\n';
  }
  writeText(dir.path("noisy.ply"), "ply\nformat ascii 1.0\nobj_info num_cols 30\nobj_info num_rows 30\nelement vertex 900\n"
                                    "property float x\nproperty float y\nproperty float z\nelement range_grid 900\n"
                                    "property list uchar int vertex_indices\nend_header\n" + points.str() + grid.str());
  const std::string placed = R"("format": "stanford-ply", "file": "noisy.ply", "translation": [0, 0, 0], "quaternion": [0, 0, 0, 1])";
  writeText(dir.path("estimated.json"), "{ \"scans\": [ { " + placed + " } ] }");
  writeText(dir.path("told.json"), "{ \"scans\": [ { " + placed + ", \"sigma\": 0.0003 } ] }");
  EXPECT_NEAR(loadManifest(dir.path("estimated.json"))[0].sigma(), 0.00005, 0.00001);
  EXPECT_DOUBLE_EQ(loadManifest(dir.path("told.json"))[0].sigma(), 0.0003);
  writeText(dir.path("zero.json"), "{ \"scans\": [ { " + placed + ", \"sigma\": 0 } ] }");
  expectManifestError(dir.path("zero.json"), "scans[0]: 'sigma' must be positive");
}

TEST(Manifest, ListsTheBunny) {
  if (test::sharedData("").empty()) GTEST_SKIP() << "../shared/data is absent";
  TempDir dir;
  writeText(dir.path("bunny.json"), "{ \"scans\": [ { \"format\": \"stanford-conf\", \"file\": \"" +
                                        test::sharedData("stanford/bunny/bun.conf") + "\", \"sigma\": 0.0003 } ] }");
  const auto maps = loadManifest(dir.path("bunny.json"));
  ASSERT_EQ(maps.size(), 10u);
  EXPECT_DOUBLE_EQ(maps[3].sigma(), 0.0003);
}

}  // namespace
}  // namespace levelfuse::io

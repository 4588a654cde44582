// TUM RGB-D folders: the lists, matching frames to poses by time, and the
// frames of a synthetic scene landing on it.

#include "support/DepthFolders.h"
#include "support/Files.h"
#include "support/InputErrors.h"

#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/TumScans.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace levelfuse::io {
namespace {

using openvdb::Vec3d;
using test::expectInputError;
using test::TempDir;
using test::writeText;

/// Poses every 10 ms from t = 100 s, the camera sliding along x and turning
/// about x and y, so that each pose differs; frames between them.
test::TumFixture slidingCamera() {
  test::TumFixture f;
  for (int i = 0; i <= 20; ++i) {
    test::CameraPose p;
    p.position = Vec3d(0.01 * i, -0.2, 0.3);
    p.rotation = test::rotationAbout(Vec3d(1.0, 0.6 - 0.05 * i, 0.0), 25.0 - i);
    f.poses.push_back({100.0 + 0.01 * i, p});
  }
  f.frameTimes = {100.003, 100.052, 100.118, 100.197};
  return f;
}

TEST(TumFolder, EachFrameTakesTheNearestPoseAndLandsOnTheScene) {
  TempDir dir;
  const test::TumFixture f = slidingCamera();
  test::writeTumFolder(dir.path("tum"), f);
  const std::vector<RangeMap> maps = loadScans(dir.path("tum"));
  ASSERT_EQ(maps.size(), 4u);
  EXPECT_EQ(maps[1].name(), "100.052000.png");
  const int nearest[] = {0, 5, 12, 20};
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const Vec3d expected = f.poses[static_cast<std::size_t>(nearest[i])].pose.position;
    EXPECT_NEAR((maps[i].scannerPosition() - expected).length(), 0.0, 1e-9) << "frame " << i;
    // Wrong quaternion order or sign, wrong pose direction or wrong depth
    // units put the readings elsewhere than on the plane z = 2.
    EXPECT_EQ(maps[i].validCount(), static_cast<std::size_t>(f.width * f.height)) << "frame " << i;
    EXPECT_LT(test::farthestFromPlane(maps[i], f.planeZ), 1e-3) << "frame " << i;  // 1/5000 m steps, tilted
  }
}

/// Writes `folder`/rgb.txt listing one colour PNG of `width` x `height` pixels per (time, colour).
void writeColourImages(const std::string& folder, const std::vector<std::pair<double, Rgb8>>& images, int width,
                       int height) {
  std::filesystem::create_directories(folder + "/rgb");
  std::string list = "# colour images\n";
  OutputSet outputs;
  for (const auto& [time, colour] : images) {
    const std::string name = "rgb/" + std::to_string(time) + ".png";
    list += std::to_string(time) + " " + name + "\n";
    writeColourPng(outputs, folder + "/" + name,
                   ColourImage{width, height, std::vector<Rgb8>(static_cast<std::size_t>(width) * height, colour)});
  }
  outputs.commit();
  writeText(folder + "/rgb.txt", list);
}

TEST(TumFolder, EachFrameTakesTheColourImageNearestInTime) {
  TempDir dir;
  const test::TumFixture f = slidingCamera();  // frames at 100.003, 100.052, 100.118, 100.197
  test::writeTumFolder(dir.path("tum"), f);
  const Rgb8 red{255, 0, 0}, green{0, 255, 0}, blue{0, 0, 255};
  // The third frame's nearest colour image is 0.032 s away: beyond 0.02 s, none.
  writeColourImages(dir.path("tum"), {{100.060, green}, {100.004, red}, {100.150, blue}}, f.width, f.height);
  const std::vector<RangeMap> maps = loadScans(dir.path("tum"));
  ASSERT_EQ(maps.size(), 4u);
  ASSERT_TRUE(maps[0].hasColours());
  ASSERT_TRUE(maps[1].hasColours());
  EXPECT_EQ(maps[0].colours(), std::vector<Rgb8>(maps[0].colours().size(), red));
  EXPECT_EQ(maps[1].colours(), std::vector<Rgb8>(maps[1].colours().size(), green));
  EXPECT_FALSE(maps[2].hasColours());
  EXPECT_FALSE(maps[3].hasColours());
  // A colour image of another size than the depth image is refused, naming it.
  writeColourImages(dir.path("tum"), {{100.004, red}}, f.width + 1, f.height);
  expectInputError([&] { loadScans(dir.path("tum")); }, dir.path("tum/rgb/100.004000.png"),
                   "must be registered to it, pixel for pixel");
}

TEST(TumFolder, DepthUnitsAreFiveThousandPerMetreUnlessTold) {
  TempDir dir;
  test::TumFixture f;
  f.poses = {{1.0, test::CameraPose{}}};
  f.frameTimes = {1.0};
  test::writeTumFolder(dir.path("tum"), f);
  EXPECT_NEAR(loadScans(dir.path("tum"))[0].reading(3, 3), 2.0, 1e-4);  // straight at the plane 2 m away
  ScanLoadOptions options;
  options.depthScale = 0.0004;  // the user's
  EXPECT_NEAR(loadScans(dir.path("tum"), options)[0].reading(3, 3), 4.0, 2e-4);
}

TEST(TumFolder, IntrinsicsFromTheFolderOrTheSequencesKinect) {
  TempDir dir;
  test::TumFixture f;
  f.poses = {{1.0, test::CameraPose{}}};
  f.frameTimes = {1.0};
  test::writeTumFolder(dir.path("with-file"), f);
  EXPECT_DOUBLE_EQ(loadTumFolder(dir.path("with-file"))[0].pinholeProjection().fx, 12.0);
  f.writeIntrinsics = false;
  test::writeTumFolder(dir.path("rgbd_dataset_freiburg1_xyz"), f);
  const PinholeProjection fr1 = loadTumFolder(dir.path("rgbd_dataset_freiburg1_xyz"))[0].pinholeProjection();
  EXPECT_DOUBLE_EQ(fr1.fx, 517.3);
  EXPECT_DOUBLE_EQ(fr1.fy, 516.5);
  EXPECT_DOUBLE_EQ(fr1.cx, 318.6);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.3);
  test::writeTumFolder(dir.path("rgbd_dataset_freiburg3_office"), f);
  EXPECT_DOUBLE_EQ(tumIntrinsics(dir.path("rgbd_dataset_freiburg3_office") + "/").fx, 535.4);
  test::writeTumFolder(dir.path("desk"), f);
  EXPECT_DOUBLE_EQ(tumIntrinsics(dir.path("desk")).fx, 517.3);
}

TEST(TumFolder, StrideAndMaximumDepth) {
  TempDir dir;
  const test::TumFixture f = slidingCamera();
  test::writeTumFolder(dir.path("tum"), f);
  ScanLoadOptions options;
  options.frameStride = 3;
  const std::vector<RangeMap> strided = loadScans(dir.path("tum"), options);
  ASSERT_EQ(strided.size(), 2u);
  EXPECT_EQ(strided[1].name(), "100.197000.png");
  // The first frame sees the plane from about 1.4 to 2.8 m.
  options.frameStride = 1;
  options.maxDepth = 2.2;
  const RangeMap near = loadScans(dir.path("tum"), options)[0];
  EXPECT_GT(near.validCount(), 0u);
  EXPECT_LT(near.validCount(), static_cast<std::size_t>(f.width * f.height));
  for (int v = 0; v < near.height(); ++v)
    for (int u = 0; u < near.width(); ++u)
      if (near.valid(u, v)) {
        EXPECT_LE(near.reading(u, v), 2.2f);
      }
}

TEST(TumFolder, RefusesAFrameWithoutAPoseNearItsTime) {
  TempDir dir;
  test::TumFixture f = slidingCamera();
  f.frameTimes.push_back(100.26);  // 60 ms after the last pose
  test::writeTumFolder(dir.path("tum"), f);
  expectInputError([&] { loadTumFolder(dir.path("tum")); }, dir.path("tum/depth/100.260000.png"),
                   "no pose in groundtruth.txt within 0.02 s of the frame's time 100.260000 (the nearest, line 23, "
                   "is 0.06 s away)");
  ScanLoadOptions lenient;
  lenient.poseTimeTolerance = 0.1;
  EXPECT_EQ(loadTumFolder(dir.path("tum"), lenient).size(), 5u);
}

TEST(TumFolder, RefusesBadOptionsAndAMissingTrajectory) {
  TempDir dir;
  test::TumFixture f = slidingCamera();
  test::writeTumFolder(dir.path("tum"), f);
  ScanLoadOptions options;
  options.maxDepth = std::nan("");
  expectInputError([&] { loadScans(dir.path("tum"), options); }, dir.path("tum"), "the maximum depth must be positive");
  options.maxDepth = 1.0;
  options.frameStride = 0;
  expectInputError([&] { loadScans(dir.path("tum"), options); }, dir.path("tum"), "the frame stride must be at least 1");
  std::filesystem::remove(dir.path("tum/groundtruth.txt"));
  expectInputError([&] { loadScans(dir.path("tum")); }, dir.path("tum"), "without groundtruth.txt");
}

TEST(TumLists, CommentsBlankLinesAndCarriageReturns) {
  TempDir dir;
  writeText(dir.path("depth.txt"), "# depth maps\r\n\r\n  1305031102.160407 depth/1305031102.160407.png\r\n"
                                   "1305031102.194330 depth/1305031102.194330.png # no\n");
  expectInputError([&] { readTumImageList(dir.path("depth.txt")); }, dir.path("depth.txt"),
                   "line 4: unexpected '#' after the file name");
  writeText(dir.path("depth.txt"), "# depth maps\r\n\r\n  1305031102.160407 depth/1305031102.160407.png\r\n");
  const std::vector<TumFrame> frames = readTumImageList(dir.path("depth.txt"));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].file, "depth/1305031102.160407.png");
  EXPECT_EQ(frames[0].line, 3);
  EXPECT_NEAR(frames[0].time, 1305031102.160407, 1e-6);
}

TEST(TumLists, PosesSortedByTimeAndMatchedToTheNearest) {
  TempDir dir;
  writeText(dir.path("gt.txt"), "2.0 0 0 2 0 0 0 1\n1.0 0 0 1 0 0 0 1\n3.0 0 0 3 0 0 0.7071068 0.7071068\n");
  const std::vector<TumPose> poses = readTumTrajectory(dir.path("gt.txt"));
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_EQ(poses[0].line, 2);
  EXPECT_EQ(nearestPose(poses, -5.0).line, 2);
  EXPECT_EQ(nearestPose(poses, 1.4).line, 2);
  EXPECT_EQ(nearestPose(poses, 1.6).line, 1);
  EXPECT_EQ(nearestPose(poses, 2.9).line, 3);
  EXPECT_EQ(nearestPose(poses, 9.0).line, 3);
  // 90 degrees about z: the camera's x axis points along the world's y.
  const Vec3d x = poses[2].cameraToWorld.transform(Vec3d(1, 0, 0));
  EXPECT_NEAR((x - Vec3d(0, 1, 3)).length(), 0.0, 1e-6);
}

TEST(TumLists, RefuseMalformedLines) {
  TempDir dir;
  const auto trajectoryError = [&](const std::string& text, const std::string& fragment) {
    writeText(dir.path("gt.txt"), text);
    expectInputError([&] { readTumTrajectory(dir.path("gt.txt")); }, dir.path("gt.txt"), fragment);
  };
  trajectoryError("1 0 0 0 0 0 0 2\n", "line 1: the quaternion has norm 2.000000, not 1: not a rotation");
  trajectoryError("1 0 0 0 0 0 0 0\n", "line 1: the quaternion is zero");
  trajectoryError("1 0 0 nan 0 0 0 1\n", "line 1: 'nan' is not a finite number");
  trajectoryError("1 0 0 0 0 0 0 1 7\n", "line 1: unexpected '7' after the quaternion");
  trajectoryError("# nothing\n", "no poses");
  writeText(dir.path("depth.txt"), "1.0\n");
  expectInputError([&] { readTumImageList(dir.path("depth.txt")); }, dir.path("depth.txt"),
                   "line 1: expected 'timestamp filename'");
  expectInputError([&] { readTumImageList(dir.path("none.txt")); }, dir.path("none.txt"), "no such file");
}

}  // namespace
}  // namespace levelfuse::io

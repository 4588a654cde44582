// Depth images, intrinsics and poses; the 7-Scenes frames.

#include "support/Files.h"
#include "support/InputErrors.h"
#include "support/TestSupport.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/images/DepthImages.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace levelfuse::io {
namespace {

using test::expectInputError;
using test::TempDir;
using test::writeText;


TEST(DepthPng, ReadsSixteenBitMillimetres) {
  TempDir dir;
  test::writePng(dir.path("d.png"), 3, 2, 16, 1, {0, 1000, 4000, 65535, 500, 1234});
  const DepthImage image = readDepthPng(dir.path("d.png"));
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  EXPECT_TRUE(std::isnan(image.depth[0]));  // 0: no reading
  EXPECT_FLOAT_EQ(image.depth[1], 1.0f);
  EXPECT_FLOAT_EQ(image.depth[2], 4.0f);
  EXPECT_TRUE(std::isnan(image.depth[3]));  // 65535: no reading
  EXPECT_FLOAT_EQ(image.depth[5], 1.234f);
  EXPECT_FLOAT_EQ(readDepthPng(dir.path("d.png"), 0.0002).depth[4], 0.1f);
}

TEST(DepthPng, RefusesOtherImages) {
  TempDir dir;
  test::writePng(dir.path("8bit.png"), 2, 2, 8, 1, {1, 2, 3, 4});
  expectInputError([&] { readDepthPng(dir.path("8bit.png")); }, dir.path("8bit.png"), "8-bit samples");
  test::writePng(dir.path("rgb.png"), 2, 2, 16, 3, std::vector<std::uint16_t>(12, 7));
  expectInputError([&] { readDepthPng(dir.path("rgb.png")); }, dir.path("rgb.png"), "not a grayscale image");
  // A valid header, then a cut: libpng's error comes back as a clear message.
  test::writePng(dir.path("cut.png"), 64, 64, 16, 1, std::vector<std::uint16_t>(64 * 64, 1234));
  const auto size = std::filesystem::file_size(dir.path("cut.png"));
  std::filesystem::resize_file(dir.path("cut.png"), size / 2);
  expectInputError([&] { readDepthPng(dir.path("cut.png")); }, dir.path("cut.png"), "truncated PNG data");
  writeText(dir.path("text.png"), "not an image at all");
  expectInputError([&] { readDepthPng(dir.path("text.png")); }, dir.path("text.png"), "not a PNG file");
  expectInputError([&] { readDepthPng(dir.path("none.png")); }, dir.path("none.png"), "no such file");
}

std::string pfm(int width, int height, const std::vector<float>& rowsBottomUp, bool declaredPixels = true) {
  std::string s = "Pf\n" + std::to_string(declaredPixels ? width : width * 1000) + " " + std::to_string(height) +
                  "\n-1.0\n";
  s.append(reinterpret_cast<const char*>(rowsBottomUp.data()), rowsBottomUp.size() * sizeof(float));
  return s;
}

TEST(DepthPfm, ReadsFloatMetresTopDown) {
  TempDir dir;
  // Bottom row first in the file: (1, 2), then the top row (3, NaN).
  writeText(dir.path("d.pfm"), pfm(2, 2, {1.0f, 2.0f, 3.0f, std::nanf("")}));
  const DepthImage image = readDepthPfm(dir.path("d.pfm"));
  EXPECT_FLOAT_EQ(image.depth[0], 3.0f);
  EXPECT_TRUE(std::isnan(image.depth[1]));
  EXPECT_FLOAT_EQ(image.depth[2], 1.0f);
  writeText(dir.path("cut.pfm"), pfm(2, 2, {1.0f, 2.0f}));
  expectInputError([&] { readDepthPfm(dir.path("cut.pfm")); }, dir.path("cut.pfm"), "truncated");
  writeText(dir.path("huge.pfm"), "Pf\n1000000 1000000\n-1.0\n");
  expectInputError([&] { readDepthPfm(dir.path("huge.pfm")); }, dir.path("huge.pfm"), "too large");
  writeText(dir.path("colour.pfm"), "PF\n1 1\n-1.0\n123456789012");
  expectInputError([&] { readDepthPfm(dir.path("colour.pfm")); }, dir.path("colour.pfm"), "colour PFM");
}

TEST(DepthPfm, ReadsHeadersWhoseLinesEndInCrLf) {
  TempDir dir;
  std::string text = pfm(2, 2, {1.0f, 2.0f, 3.0f, 4.0f});
  for (std::size_t at = text.find('\n'); at != std::string::npos && at < 16; at = text.find('\n', at + 2))
    text.insert(at, "\r");
  ASSERT_EQ(text.rfind("Pf\r\n2 2\r\n-1.0\r\n", 0), 0u);
  writeText(dir.path("crlf.pfm"), text);
  const DepthImage image = readDepthPfm(dir.path("crlf.pfm"));
  EXPECT_EQ(image.depth, (std::vector<float>{3.0f, 4.0f, 1.0f, 2.0f}));
}

TEST(DepthImages, RefuseImagesBeyondTheMemoryBudget) {
  TempDir dir;
  test::writePng(dir.path("d.png"), 64, 32, 16, 1, std::vector<std::uint16_t>(64 * 32, 1500));
  writeText(dir.path("d.pfm"), pfm(64, 32, std::vector<float>(64 * 32, 1.5f)));
  const MemoryBudget budget(10000);
  const std::string fragment =
      "an image of 64 x 32 pixels needs about 16 KiB of memory, more than the 9.77 KiB levelfuse may use: crop";
  expectInputError([&] { readDepthPng(dir.path("d.png"), 0.001, {0u, 65535u}, budget); }, dir.path("d.png"), fragment);
  expectInputError([&] { readDepthPfm(dir.path("d.pfm"), true, budget); }, dir.path("d.pfm"), fragment);
  EXPECT_NO_THROW(readDepthPng(dir.path("d.png")));  // the machine's budget holds it
}

TEST(DepthFrame, KeepsReadingsWhoseSigmaOverflowsAFloat) {
  // Found by FuzzDepthPfm: 1e38 m has a sigma of 1.5e73 m, infinite as a float,
  // which the range map refused with std::invalid_argument.
  const DepthImage image{2, 2, {1.0f, 1e38f, 2.0f, 3.0f}};
  const RangeMap map = depthFrame(image, PinholeProjection{10.0, 10.0, 0.5, 0.5}, openvdb::math::Mat4d::identity(),
                                  DepthNoise(), "far");
  EXPECT_EQ(map.validCount(), 4u);
  EXPECT_FLOAT_EQ(map.reading(1, 0), 1e38f);
}

TEST(CameraFiles, IntrinsicsAndPoses) {
  TempDir dir;
  writeText(dir.path("k.txt"), "585 0 320\n0 585 240\n0 0 1\n");
  const PinholeProjection k = readIntrinsics(dir.path("k.txt"));
  EXPECT_DOUBLE_EQ(k.fx, 585.0);
  EXPECT_DOUBLE_EQ(k.cy, 240.0);
  writeText(dir.path("bad.txt"), "585 0 320\n0 585 240\n");
  expectInputError([&] { readIntrinsics(dir.path("bad.txt")); }, dir.path("bad.txt"), "expected 9 numbers, found 6");
  writeText(dir.path("skew.txt"), "585 1 320\n0 585 240\n0 0 1\n");
  expectInputError([&] { readIntrinsics(dir.path("skew.txt")); }, dir.path("skew.txt"), "not a pinhole intrinsics");

  // A camera-to-world pose: 90 degrees about z, then a translation.
  writeText(dir.path("pose.txt"), "0 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 0 1\n");
  const openvdb::math::Mat4d pose = readPose(dir.path("pose.txt"));
  const openvdb::Vec3d p = pose.transform(openvdb::Vec3d(1, 0, 0));
  EXPECT_NEAR(p.x(), 1.0, 1e-12);
  EXPECT_NEAR(p.y(), 3.0, 1e-12);
  EXPECT_NEAR(p.z(), 3.0, 1e-12);
  // Nearly rigid (as tracked poses are): projected onto the nearest rotation.
  writeText(dir.path("near.txt"), "1.002 0.001 0 0\n0 0.999 0 0\n0 0 1 0\n0 0 0 1\n");
  const openvdb::math::Mat3d r = readPose(dir.path("near.txt")).getMat3();
  const openvdb::math::Mat3d rtr = r.transpose() * r;
  EXPECT_NEAR(rtr(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(rtr(0, 1), 0.0, 1e-12);
  writeText(dir.path("scaled.txt"), "2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n");
  expectInputError([&] { readPose(dir.path("scaled.txt")); }, dir.path("scaled.txt"), "not orthonormal");
  writeText(dir.path("inf.txt"), "1 0 0 inf\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expectInputError([&] { readPose(dir.path("inf.txt")); }, dir.path("inf.txt"), "not finite");
}

TEST(SevenScenes, FramesLoadWithSensibleDepths) {
  if (test::sharedData("").empty()) GTEST_SKIP() << "../shared/data is absent: the 7-Scenes frames are not tested";
  const std::string folder = test::sharedData("7scenes/");
  const PinholeProjection k = readIntrinsics(folder + "camera-intrinsics.txt");
  EXPECT_DOUBLE_EQ(k.fx, 585.0);
  std::size_t frames = 0;
  for (int f = 0; f <= 980; f += 20) {
    char name[32];
    std::snprintf(name, sizeof(name), "frame-%06d", f);
    const DepthImage image = readDepthPng(folder + name + ".depth.png");
    ASSERT_EQ(image.width, 640);
    ASSERT_EQ(image.height, 480);
    std::vector<float> valid;
    for (float d : image.depth)
      if (d == d) valid.push_back(d);
    ASSERT_GT(valid.size(), image.depth.size() / 2) << name;
    std::sort(valid.begin(), valid.end());
    // Kinect v1 indoors: the bulk of the readings between half a metre and 4 m.
    EXPECT_GT(valid[valid.size() / 100], 0.4f) << name;
    EXPECT_LT(valid[valid.size() * 99 / 100], 4.5f) << name;
    const auto pose = readPose(folder + name + ".pose.txt");
    const RangeMap map = depthFrame(image, k, pose, DepthNoise{}, name);
    EXPECT_EQ(map.validCount(), valid.size());
    ++frames;
  }
  EXPECT_EQ(frames, 50u);
}

}  // namespace
}  // namespace levelfuse::io

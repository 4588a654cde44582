// Shaded previews of level sets.

#include "support/Files.h"
#include "support/TestSupport.h"

#include <levelfuse/io/Preview.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace levelfuse::io {
namespace {

int brightness(const test::PngImage& image, int x, int y) {
  const std::uint8_t* p = image.pixel(x, y);
  return p[0] + p[1] + p[2];
}

TEST(Preview, ShowsTheSurfaceFramedInThePicture) {
  test::TempDir dir;
  const auto sphere = test::makeSphere(20.0, openvdb::Vec3d(3.0, -2.0, 1.0), 0.1);
  PreviewOptions options;
  options.width = 160;
  options.height = 120;
  writePreviewPng(*sphere, dir.path("s.png"), options);
  const test::PngImage image = test::readPng8(dir.path("s.png"));
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  // The sphere fills the middle of the picture and leaves the corners; the
  // lit surface is brighter than the background.
  EXPECT_GT(brightness(image, 80, 60), brightness(image, 2, 2) + 150);
  EXPECT_GT(brightness(image, 80, 60), brightness(image, 157, 117) + 150);
  // Framed: the sphere's silhouette spans most of the picture's height.
  int rows = 0;
  for (int y = 0; y < 120; ++y) rows += std::abs(brightness(image, 80, y) - brightness(image, 80, 0)) > 40;
  EXPECT_GT(rows, 80);
  EXPECT_LT(rows, 118);
}

TEST(Preview, RefusesWhatItCannotShowAndLeavesNoFile) {
  test::TempDir dir;
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  EXPECT_THROW(writePreviewPng(*fog, dir.path("fog.png")), std::invalid_argument);
  auto empty = openvdb::FloatGrid::create(3.0f);
  empty->setGridClass(openvdb::GRID_LEVEL_SET);
  EXPECT_THROW(writePreviewPng(*empty, dir.path("empty.png")), std::invalid_argument);
  const auto sphere = test::makeSphere(10.0);
  EXPECT_THROW(writePreviewPng(*sphere, dir.path("no/such/folder/s.png")), std::runtime_error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.root()));
}

}  // namespace
}  // namespace levelfuse::io

// Shaded previews of level sets.

#include "support/Files.h"
#include "support/TestSupport.h"

#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <utility>
#include <vector>

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

/// A grid on `levelSet`'s band (a weight, a colour): `above` where z > `z`,
/// else `below`; `background` off the band.
template <typename GridT>
typename GridT::Ptr splitAt(const openvdb::FloatGrid& levelSet, double z, const typename GridT::ValueType& above,
                            const typename GridT::ValueType& below, const typename GridT::ValueType& background) {
  auto grid = GridT::create(background);
  grid->setTransform(levelSet.transform().copy());
  grid->setTree(std::make_shared<typename GridT::TreeType>(levelSet.tree(), background, openvdb::TopologyCopy()));
  for (auto it = grid->beginValueOn(); it; ++it) it.setValue(grid->indexToWorld(it.getCoord()).z() > z ? above : below);
  return grid;
}

openvdb::FloatGrid::Ptr weightSplitAt(const openvdb::FloatGrid& levelSet, double z, float inFront, float behind) {
  return splitAt<openvdb::FloatGrid>(levelSet, z, inFront, behind, 0.0f);
}

/// A small picture looking straight down (-z).
PreviewOptions smallViewFromAbove() {
  PreviewOptions options;
  options.width = 160;
  options.height = 120;
  options.toward = openvdb::Vec3d(0.0, 0.0, 1.0);
  return options;
}

TEST(Preview, LeavesOutTheSurfaceWhereTheWeightIsBelowItsMinimum) {
  test::TempDir dir;
  const openvdb::Vec3d centre(3.0, -2.0, 1.0);
  const auto sphere = test::makeSphere(20.0, centre, 0.1);
  PreviewOptions options = smallViewFromAbove();
  options.minWeight = 0.5;
  const auto picture = [&](float inFront, float behind, const std::string& name) {
    options.weight = weightSplitAt(*sphere, centre.z(), inFront, behind);
    writePreviewPng(*sphere, dir.path(name), options);
    return test::readPng8(dir.path(name));
  };
  const test::PngImage all = picture(1.0f, 1.0f, "all.png"), none = picture(0.0f, 0.0f, "none.png");
  const test::PngImage back = picture(0.0f, 1.0f, "back.png");
  // Nothing drawn: the background alone, which is the same along a row.
  EXPECT_EQ(brightness(none, 80, 60), brightness(none, 2, 60));
  EXPECT_GT(brightness(all, 80, 60), brightness(none, 80, 60) + 150);
  // Seen through the front half that is left out: the inside of the back half.
  EXPECT_NE(brightness(back, 80, 60), brightness(none, 80, 60));
  EXPECT_NE(brightness(back, 80, 60), brightness(all, 80, 60));
}

TEST(Preview, PaintsTheSurfaceInItsColourWithNoPixelFromBehind) {
  test::TempDir dir;
  const openvdb::Vec3d centre(3.0, -2.0, 1.0);
  const auto sphere = test::makeSphere(20.0, centre, 0.1);
  PreviewOptions options = smallViewFromAbove();
  options.colour = splitAt<openvdb::Vec3fGrid>(*sphere, centre.z(), openvdb::Vec3f(0.8f, 0.1f, 0.1f),
                                               openvdb::Vec3f(0.1f, 0.1f, 0.8f), openvdb::Vec3f(0.5f));
  writePreviewPng(*sphere, dir.path("s.png"), options);
  const test::PngImage image = test::readPng8(dir.path("s.png"));
  // Seen from straight above the plane that splits the colours (z), the
  // sphere is the upper half's red; no pixel shows the lower half's blue
  // through it (every ray stops at the first surface it meets).
  int red = 0, blue = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      red += p[0] > p[2] + 60;
      blue += p[2] > p[0] + 60;
    }
  EXPECT_GT(red, 2000);  // the sphere's disc, about 2300 pixels
  EXPECT_EQ(blue, 0);
}

TEST(Preview, LooksFromAPlacedCamera) {
  test::TempDir dir;
  const auto sphere = test::makeSphere(20.0, openvdb::Vec3d(0.0), 0.1);
  PreviewOptions options;
  options.width = 64;
  options.height = 48;
  options.camera = PreviewCamera{openvdb::Vec3d(0.0), openvdb::Vec3d(1.0, 0.0, 0.0), openvdb::Vec3d(0.0, 0.0, 1.0)};
  writePreviewPng(*sphere, dir.path("inside.png"), options);
  options.camera.reset();
  writePreviewPng(*sphere, dir.path("outside.png"), options);
  const test::PngImage inside = test::readPng8(dir.path("inside.png"));
  const test::PngImage outside = test::readPng8(dir.path("outside.png"));
  // From the centre every ray meets the sphere; from outside the corners show the background.
  for (const auto& [x, y] : {std::pair{1, 1}, std::pair{62, 1}, std::pair{1, 46}, std::pair{62, 46}})
    EXPECT_NE(brightness(inside, x, y), brightness(outside, x, y)) << x << ", " << y;
}

TEST(Preview, SeenByADepthFrameLooksFromItsCameraInsideTheScene) {
  // A room 4 x 3 x 2.4 m seen from inside, by a camera near one wall that
  // turns to each of the four walls.
  const auto room = [](const openvdb::Vec3d& p) {
    return std::min({2.0 - std::fabs(p.x()), 1.5 - std::fabs(p.y()), 1.2 - std::fabs(p.z())});
  };
  const openvdb::Vec3d eye(-1.5, 0.3, 0.2);
  std::vector<RangeMap> frames;
  for (const openvdb::Vec3d& look : {openvdb::Vec3d(1, 0, 0), openvdb::Vec3d(0, 1, 0), openvdb::Vec3d(-1, 0, 0),
                                     openvdb::Vec3d(0, -1, 0)})
    frames.push_back(synth::renderDistanceFunction(room, synth::pinholeView(eye, eye + look, 60.0, 64, 48),
                                                   synth::Noise{}, 0.01));
  const RangeMap& frame = frames.front();
  const PreviewOptions options = seenByFrame(frame);
  ASSERT_TRUE(options.camera.has_value());
  EXPECT_NEAR((options.camera->eye - eye).length(), 0.0, 1e-9);
  // Inside the box of what the frames saw, looking along the first one's optical axis.
  openvdb::BBoxd seen;
  for (const RangeMap& map : frames)
    for (int v = 0; v < map.height(); ++v)
      for (int u = 0; u < map.width(); ++u)
        if (map.valid(u, v)) seen.expand(map.readingPoint(u, v));
  EXPECT_TRUE(seen.isInside(options.camera->eye)) << seen;
  const openvdb::Vec3d centre = frame.pointAt(frame.pinholeProjection().cx, frame.pinholeProjection().cy, 1.0);
  EXPECT_NEAR((centre - eye).unit().dot(options.camera->forward.unit()), 1.0, 1e-9);
  // The picture has the frame's aspect and vertical field of view.
  EXPECT_EQ(options.width * 48, options.height * 64);
  const double tanHalfHeight = 0.5 * 48 / frame.pinholeProjection().fy;
  EXPECT_NEAR(options.fieldOfViewDegrees, 2.0 * std::atan(tanHalfHeight) * 180.0 / M_PI, 1e-9);
  // Up in the picture is up in the frame: against its image rows.
  const openvdb::Vec3d down = frame.pointAt(frame.pinholeProjection().cx, 47.0, 1.0) - centre;
  EXPECT_LT(down.dot(options.camera->up), 0.0);

  const RangeMap scan = synth::renderDistanceFunction(
      room, synth::orthographicView(openvdb::Vec3d(0, 0, -1), openvdb::Vec3d(0.0), 1.0, 16), synth::Noise{}, 0.01);
  EXPECT_THROW(seenByFrame(scan), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse::io

// The colour the scans saw, carried to the reconstructed surface: a sphere
// painted in two halves, and a thin plate whose two faces were seen by two
// scanners in two colours.

#include "support/Files.h"
#include "support/TestSupport.h"

#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/SurfaceColour.h>
#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using openvdb::Vec3f;

constexpr Rgb8 kRed{200, 40, 30}, kBlue{30, 60, 200};

/// The seam between the halves blurs over a few voxels (readings of both
/// colours meet in the windows there; grazing rays carry the noise along z):
/// colours are checked this many voxels away from it.
constexpr double kSeam = 5.0;

Vec3f unit(const Rgb8& c) { return Vec3f(c[0], c[1], c[2]) / 255.0f; }

/// The largest difference of a channel between two colours.
float colourError(const Vec3f& a, const Vec3f& b) {
  return std::max({std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1]), std::fabs(a[2] - b[2])});
}

/// The unit sphere from six noisy parallel-ray scans, its upper half (z >= 0) red and its lower half blue.
std::vector<RangeMap> paintedSphereScans() {
  synth::SceneOptions options;
  options.resolution = 100;
  options.noise = 0.01;
  synth::Scene scene = synth::analyticScene(synth::standardShape(shapes::AnalyticShape::Kind::kSphere), options);
  for (RangeMap& map : scene.maps) synth::paintReadings(map, synth::twoColours(Vec3d(0.0), Vec3d(0, 0, 1), kRed, kBlue));
  return std::move(scene.maps);
}

TEST(SurfaceColour, ATwoColouredSphereComesBackWithEachHalfInItsColour) {
  const ReconstructionResult result = Reconstructor(paintedSphereScans()).run();
  ASSERT_TRUE(result.colour);
  EXPECT_EQ(result.colour->getName(), kColourGridName);
  EXPECT_EQ(result.colour->getGridClass(), openvdb::GRID_UNKNOWN);
  const double h = result.levelSet->voxelSize()[0];
  const ColourSampler colour(*result.colour);
  std::size_t points = 0, wrong = 0;
  float worst = 0.0f;
  for (const Vec3d& p : zeroCrossings(*result.levelSet)) {
    if (std::fabs(p.z()) < kSeam * h) continue;
    ++points;
    const float error = colourError(colour.at(p), unit(p.z() > 0.0 ? kRed : kBlue));
    worst = std::max(worst, error);
    wrong += error > 0.02f;
  }
  EXPECT_GT(points, 10000u);
  EXPECT_EQ(wrong, 0u) << "worst channel error " << worst;
}

TEST(SurfaceColour, ThePreviewShowsTheColourOfTheFirstSurfaceEachRayMeets) {
  const ReconstructionResult result = Reconstructor(paintedSphereScans()).run();
  io::PreviewOptions options;
  options.width = 200;
  options.height = 150;
  options.toward = Vec3d(0.0, 0.0, 1.0);  // from straight above: only the red half is in sight
  options.colour = result.colour;
  const io::PreviewImage image = io::renderPreview(*result.levelSet, options);
  int red = 0, blue = 0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) {
    red += image.rgb[i] > image.rgb[i + 2] + 60;
    blue += image.rgb[i + 2] > image.rgb[i] + 60;
  }
  EXPECT_GT(red, 3000);
  EXPECT_EQ(blue, 0);
}

TEST(SurfaceColour, EachFaceOfAThinPlateTakesTheColourOfTheScannerThatFacedIt) {
  // A plate 2 x 2 x 0.1 (five voxels), seen from above by a scanner that recorded red and
  // from below by one that recorded blue: each face's colour is its own
  // scanner's, though each scanner's window reaches through the plate.
  const auto plate = [](const Vec3d& x) {
    return std::max({std::fabs(x.x()) - 1.0, std::fabs(x.y()) - 1.0, std::fabs(x.z()) - 0.05});
  };
  std::vector<RangeMap> maps;
  for (const auto& [direction, colour] : {std::pair{Vec3d(0, 0, -1), kRed}, std::pair{Vec3d(0, 0, 1), kBlue}}) {
    RangeMap map = synth::renderDistanceFunction(plate, synth::orthographicView(direction, Vec3d(0.0), 2.6, 130),
                                                 synth::Noise{}, 0.02);
    synth::paintReadings(map, [colour = colour](const Vec3d&) { return colour; });
    maps.push_back(std::move(map));
  }
  ReconstructionOptions options;
  options.voxelSize = 0.02;
  options.levels = 1;
  options.epsilon = 0.05;  // windows 0.15 deep: each reaches through the plate to the far face
  const ReconstructionResult result = Reconstructor(maps, options).run();
  ASSERT_TRUE(result.colour);
  const ColourSampler colour(*result.colour);
  std::size_t top = 0, bottom = 0, wrong = 0;
  for (const Vec3d& p : zeroCrossings(*result.levelSet)) {
    if (std::max(std::fabs(p.x()), std::fabs(p.y())) > 0.9) continue;  // the faces, not the rims
    const bool onTop = p.z() > 0.0;
    (onTop ? top : bottom) += 1;
    wrong += colourError(colour.at(p), unit(onTop ? kRed : kBlue)) > 0.02f;
  }
  EXPECT_GT(top, 5000u);
  EXPECT_GT(bottom, 5000u);
  EXPECT_EQ(wrong, 0u);
}

TEST(SurfaceColour, ScansWithoutColourGiveNoColourGrid) {
  synth::SceneOptions options;
  options.resolution = 60;
  const synth::Scene scene = synth::analyticScene(synth::standardShape(shapes::AnalyticShape::Kind::kSphere), options);
  EXPECT_FALSE(Reconstructor(scene.maps).run().colour);
}

TEST(SurfaceColour, TheMeshTakesTheColourAtItsVertices) {
  const ReconstructionResult result = Reconstructor(paintedSphereScans()).run();
  TriangleMesh mesh = meshFromLevelSet(*result.levelSet);
  paintMesh(mesh, *result.colour);
  ASSERT_EQ(mesh.rgb.size(), mesh.xyz.size());
  const double h = result.levelSet->voxelSize()[0];
  std::size_t wrong = 0;
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const float z = mesh.xyz[3 * v + 2];
    if (std::fabs(z) < kSeam * h) continue;
    const Rgb8 expected = z > 0.0f ? kRed : kBlue;
    for (int c = 0; c < 3; ++c) wrong += std::abs(int(mesh.rgb[3 * v + c]) - int(expected[c])) > 5;
  }
  EXPECT_EQ(wrong, 0u);
}

}  // namespace
}  // namespace levelfuse

// The paper's experiments reproduced, the synthetic ones (Figs. 10-15) and the
// real scans (section 6): each test asserts the paper's claim and prints the
// numbers docs/RESULTS.md records.

#include "support/TestSupport.h"

#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/HeldOutFrames.h>
#include <levelfuse/synth/Scenes.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;
using Kind = shapes::AnalyticShape::Kind;

double rmsError(const openvdb::FloatGrid& surface, const shapes::AnalyticShape& truth) {
  return rmsOver(zeroCrossings(surface), truth);
}

/// The genus of a closed surface from its mesh: V - E + F = 2 - 2 genus.
int genus(const openvdb::FloatGrid& surface) {
  const TriangleMesh mesh = meshFromLevelSet(surface);
  const long euler = static_cast<long>(mesh.vertexCount()) - static_cast<long>(mesh.triangleCount()) / 2;
  return static_cast<int>((2 - euler) / 2);
}

float valueAt(const openvdb::FloatGrid& grid, const Vec3d& p) {
  return grid.tree().getValue(openvdb::Coord::round(grid.worldToIndex(p)));
}

// Figs. 10-13: the torus from six views with Gaussian noise of 20% of its
// tube's diameter; the rms error of the surface against beta, as a fraction
// of the noise, beside the linear solution's.
TEST(Figure13, TorusErrorAgainstBeta) {
  synth::SceneOptions scan;
  scan.noise = 0.2;
  const synth::Scene scene = synth::analyticScene(synth::standardShape(Kind::kTorus), scan);
  const double sigma = scene.noiseSigma;
  ReconstructionOptions options;
  const Reconstructor defaults(scene.maps, options);
  const ForceField finest(scene.maps, defaults.forceOptions(defaults.settings().levels - 1));
  const double linear = rmsError(*finest.linearSolution(defaults.settings().voxelSize), *scene.truth) / sigma;
  std::printf("| beta (finest voxels) | rms error / noise sigma | iterations |\n| --- | --- | --- |\n");
  std::printf("| linear solution | %.3f | |\n", linear);
  double best = 1e9, atZero = 0.0, atLargest = 0.0, atDefault = 0.0;
  for (double beta : {0.0, 1.0, 3.0, 9.0, 27.0, 81.0}) {
    options.beta = beta;
    const ReconstructionResult result = Reconstructor(scene.maps, options).run();
    const double rms = rmsError(*result.levelSet, *scene.truth) / sigma;
    int iterations = 0;
    for (const LevelReport& level : result.levels) iterations += level.iterations;
    std::printf("| %g | %.3f | %d |\n", beta, rms, iterations);
    best = std::min(best, rms);
    if (beta == 0.0) atZero = rms;
    if (beta == 81.0) atLargest = rms;
  }
  {
    const ReconstructionResult result = defaults.run();
    atDefault = rmsError(*result.levelSet, *scene.truth) / sigma;
    std::printf("| default, %.2f | %.3f | |\n", defaults.settings().beta, atDefault);
  }
  EXPECT_LT(best, 0.25 * linear);   // the prior clearly beats the linear solution
  EXPECT_LT(best, 0.1);             // a tenth of the noise
  EXPECT_GT(atZero, 2.0 * best);    // too little prior: the noise shows
  EXPECT_GT(atLargest, 1.3 * best); // too much: the surface shrinks
  EXPECT_LT(atDefault, 1.3 * best); // the derived beta is near the best
}

struct MugCase {
  const char* name;
  double noise, outliers;
  double maxRmsOverHandleWidth;
};

class Figure14 : public ::testing::TestWithParam<MugCase> {};

// Figs. 14-15: the mug from ten views, without noise, with Gaussian noise of
// half its handle's width, and with 1% of the readings replaced by outliers,
// on a final grid of about 140 voxels across: a clean mug each time.
TEST_P(Figure14, MugStaysACleanMug) {
  const MugCase& c = GetParam();
  synth::SceneOptions scan;
  scan.noise = c.noise;
  scan.outliers = c.outliers;
  const synth::Scene scene = synth::analyticScene(synth::standardShape(Kind::kMug), scan);
  ReconstructionOptions options;
  options.voxelSize = 0.019;  // 140 voxels across the mug's 2.67 units
  const ReconstructionResult result = Reconstructor(scene.maps, options).run();
  const openvdb::FloatGrid& surface = *result.levelSet;
  const double rms = rmsError(surface, *scene.truth) / scene.size;
  std::printf("| %s | %.4f | %d | %d |\n", c.name, rms, insideComponents(surface), genus(surface));
  EXPECT_EQ(insideComponents(surface), 1);
  EXPECT_EQ(genus(surface), 1);  // the handle's hole, and no other
  const shapes::Mug& mug = scene.truth->mug;
  const Vec3d handleCentre = mug.centre + Vec3d(mug.radius, 0.0, 0.5 * mug.height);
  EXPECT_GT(valueAt(surface, handleCentre + Vec3d(0.5 * mug.handleBend, 0, 0)), 0.0f);  // the hole is open
  EXPECT_LT(valueAt(surface, handleCentre + Vec3d(mug.handleBend, 0, 0)), 0.0f);        // the handle is solid
  EXPECT_GT(valueAt(surface, mug.centre + Vec3d(0, 0, 0.5 * mug.height)), 0.0f);         // the cup is hollow
  EXPECT_LT(rms, c.maxRmsOverHandleWidth);
}

INSTANTIATE_TEST_SUITE_P(Mug, Figure14,
                         ::testing::Values(MugCase{"no noise", 0.0, 0.0, 0.03},
                                           MugCase{"50% noise", 0.5, 0.0, 0.1},
                                           MugCase{"1% outliers", 0.0, 0.01, 0.2}),
                         [](const auto& param) {
                           return std::string(param.index == 0 ? "NoNoise" : param.index == 1 ? "HalfHandleNoise" : "Outliers");
                         });

// Section 6 on real scans: the Stanford bunny and dragon, coarse to fine to
// 0.5 mm voxels with the default settings: one closed surface with no holes
// where the scans saw it, close to the scanner's points (docs/RESULTS.md has
// the finer grids).
struct RealCase {
  const char* name;
  const char* conf;
  Vec3d towardScanner;
  int genus;
  double maxBeyondBand, maxMeanMm, maxMedianMm;
};

std::ostream& operator<<(std::ostream& os, const RealCase& c) { return os << c.name; }

class RealScanReconstruction : public ::testing::TestWithParam<RealCase> {};

TEST_P(RealScanReconstruction, OneClosedSurfaceCloseToThePoints) {
  if (test::sharedData("").empty()) GTEST_SKIP() << "../shared/data is absent: the real scans are not tested";
  const RealCase& c = GetParam();
  io::StanfordScanOptions load;
  load.towardScanner = c.towardScanner;
  const std::vector<RangeMap> maps = io::loadStanfordScans(test::sharedData(c.conf), load);
  ReconstructionOptions options;
  options.voxelSize = 0.0005;
  const ReconstructionResult result = Reconstructor(maps, options).run();
  const openvdb::FloatGrid& surface = *result.levelSet;
  const DataFit fit = measureDataFit(surface, maps);
  std::printf("| %s | %d | %d | %.4f mm | %.4f mm | %.4f mm | %.2f%% |\n", c.name, insideComponents(surface),
              genus(surface), 1000.0 * fit.mean, 1000.0 * fit.median, 1000.0 * fit.p90, 100.0 * fit.beyondBand);
  EXPECT_EQ(insideComponents(surface), 1);
  EXPECT_EQ(genus(surface), c.genus);
  EXPECT_LT(fit.beyondBand, c.maxBeyondBand);  // no holes: a hole leaves its points beyond the band
  EXPECT_LT(1000.0 * fit.mean, c.maxMeanMm);
  EXPECT_LT(1000.0 * fit.median, c.maxMedianMm);
}

INSTANTIATE_TEST_SUITE_P(Stanford, RealScanReconstruction,
                         ::testing::Values(RealCase{"bunny", "stanford/bunny/bun.conf", Vec3d(0, 0, 1), 0, 0.001, 0.1, 0.07},
                                           RealCase{"dragon", "stanford/dragon/dragonStandRight.conf",
                                                    Vec3d(0.46, 0.04, 0.89), 2, 0.02, 0.16, 0.095}),
                         [](const auto& param) { return std::string(param.param.name); });

// Depth video (docs/RESULTS.md): the 7-Scenes sequence's frames 0, 10, ...,
// 490 at 10 mm, measured on the frames 5, 15, ..., 495 it never saw (every
// fourth pixel along both axes). The MAP evolution, started from the linear
// solution, must end no farther from them on average and with no fewer of
// their points within 2 cm. (Measured at this stride: the linear solution
// 7.062 mm and 94.25%, the evolution 7.053 mm and 94.28%; before the evolution
// clamped its force and stopped waiting for the surface no frame saw, 7.067 mm
// and 94.24%, and this test failed.)
std::vector<std::string> depthFrameStems(const std::string& folder) {
  std::vector<std::string> stems;
  const std::string suffix = ".depth.png";
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string path = entry.path().string();
    if (path.size() > suffix.size() && path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0)
      stems.push_back(path.substr(0, path.size() - suffix.size()));
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

TEST(DepthVideo, TheEvolutionEndsNoFartherFromHeldOutFramesThanTheLinearSolution) {
  const std::string folder = test::sharedData("7scenes-seq");
  if (folder.empty() || !std::filesystem::exists(folder))
    GTEST_SKIP() << "../shared/data/7scenes-seq is absent: depth video is not tested on real frames";
  const std::vector<std::string> stems = depthFrameStems(folder);
  ASSERT_EQ(stems.size(), 500u);
  io::ScanLoadOptions load;
  load.frameStride = 10;
  const std::vector<RangeMap> frames = io::loadScans(folder, load);
  ASSERT_EQ(frames.size(), 50u);
  const PinholeProjection intrinsics = io::readIntrinsics(folder + "/camera-intrinsics.txt");
  std::vector<RangeMap> heldOut;
  for (const std::size_t i : splitFrames(stems.size(), 10, 5).heldOut)
    heldOut.push_back(io::depthFrame(io::readDepthPng(stems[i] + ".depth.png"), intrinsics,
                                     io::readPose(stems[i] + ".pose.txt"), io::DepthNoise(), stems[i]));
  ReconstructionOptions options;
  options.voxelSize = 0.01;
  const Reconstructor reconstructor(frames, options);
  HeldOutOptions ruler;
  ruler.stride = 4;
  const HeldOutAccuracy linear = measureHeldOutFrames(*reconstructor.linearSolution(), heldOut, ruler);
  const HeldOutAccuracy map = measureHeldOutFrames(*reconstructor.run().levelSet, heldOut, ruler);
  std::printf("| linear solution | %.4f mm | %.3f%% |\n| MAP evolution | %.4f mm | %.3f%% |\n",
              1000.0 * linear.distances.mean, 100.0 * linear.within[1], 1000.0 * map.distances.mean,
              100.0 * map.within[1]);
  ASSERT_GT(map.distances.readings, 800000u);
  EXPECT_LE(map.distances.mean, linear.distances.mean);
  EXPECT_GE(map.within[1], linear.within[1]);
}

}  // namespace
}  // namespace levelfuse

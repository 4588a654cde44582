// The reconstruction pipeline on synthetic scans with known answers.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/MeshTrim.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <openvdb/tools/Diagnostics.h>
#include <openvdb/tools/Interpolation.h>
#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

const shapes::Sphere kSphere{Vec3d(0.013, -0.021, 0.007), 1.0};

/// Six views of the unit sphere, 120 x 120 pixels, with Gaussian range noise.
std::vector<RangeMap> noisySphere(double sigma, std::uint64_t seed = 1) {
  std::vector<RangeMap> maps;
  for (const synth::View& view : synth::sixAxisViews(Vec3d(0.0), 2.4, 120)) {
    synth::Noise noise;
    noise.gaussianSigma = sigma;
    noise.seed = seed++;
    maps.push_back(synth::renderDistanceFunction(kSphere, view, noise, std::max(sigma, 0.002)));
  }
  return maps;
}

ReconstructionOptions smallOptions() {
  ReconstructionOptions options;
  options.voxelSize = 0.04;  // 50 voxels across the sphere
  options.levels = 2;
  return options;
}

TEST(Reconstructor, ResolvesItsDefaultsFromTheData) {
  const Reconstructor r(noisySphere(0.01));
  const ReconstructionSettings& o = r.settings();
  EXPECT_NEAR(o.voxelSize, 0.02, 1e-9);  // the views' ray spacing, 2.4 / 120
  EXPECT_NEAR(o.epsilon, 0.01, 1e-9);    // sigma
  EXPECT_NEAR(o.beta, 0.5, 1e-9);        // sigma is half a voxel: the floor
  EXPECT_EQ(o.levels, 2);                // 100 voxels across: the coarsest grid about 64
  EXPECT_NEAR(r.voxelSize(0), 2.0 * o.voxelSize, 1e-12);
  EXPECT_NEAR(r.voxelSize(1), o.voxelSize, 1e-12);
  EXPECT_GT(r.bounds().extents().x(), 1.9);
  EXPECT_THROW(Reconstructor(std::vector<RangeMap>{}), std::invalid_argument);
  ReconstructionOptions bad;
  bad.voxelSize = 1e-9;
  EXPECT_THROW(Reconstructor(noisySphere(0.01), bad), std::invalid_argument);  // 10^9 voxels across
  EXPECT_NEAR(Reconstructor(noisySphere(0.08)).settings().beta, 4.0, 1e-9);  // sigma / voxel
}

TEST(Reconstructor, RunsWithSettingsResolvedOnceAsItWouldResolveThem) {
  ReconstructionOptions given = smallOptions();
  given.tolerance = 0.1;
  given.name = "ball";
  given.memoryBudget = MemoryBudget(1u << 30);
  const std::vector<RangeMap> maps = noisySphere(0.01);
  const ReconstructionSettings settings = resolveReconstructionSettings(given, ScanSummary(maps));
  EXPECT_EQ(settings.voxelSize, 0.04);
  EXPECT_EQ(settings.levels, 2);
  EXPECT_NEAR(settings.epsilon, 0.01, 1e-9);  // derived: sigma
  EXPECT_EQ(settings.dataTerm, DataTermSource::kPerMap);  // derived: six maps
  EXPECT_EQ(settings.tolerance, 0.1);
  EXPECT_EQ(settings.name, "ball");
  EXPECT_EQ(settings.memoryBudget.bytes(), 1u << 30);
  // Resolving the settings as options gives them back.
  const ReconstructionSettings again = resolveReconstructionSettings(optionsOf(settings), ScanSummary(maps));
  EXPECT_EQ(again.beta, settings.beta);
  EXPECT_EQ(again.epsilon, settings.epsilon);
  EXPECT_EQ(again.dataTerm, settings.dataTerm);
  // A reconstructor given the settings runs as one given the options.
  const Reconstructor fromSettings(noisySphere(0.01), settings), fromOptions(noisySphere(0.01), given);
  EXPECT_EQ(fromSettings.settings().beta, fromOptions.settings().beta);
  ReconstructionSettings fewIterations = settings;
  fewIterations.maxIterations = 2;
  given.maxIterations = 2;
  given.minIterations = 2;
  fewIterations.minIterations = 2;
  const ReconstructionResult a = Reconstructor(noisySphere(0.01), fewIterations).run();
  const ReconstructionResult b = Reconstructor(noisySphere(0.01), given).run();
  std::string why;
  EXPECT_TRUE(test::identical(*a.levelSet, *b.levelSet, &why)) << why;
}

TEST(Reconstructor, OnAFusionTakesOnlyTheFusionsGrids) {
  const std::vector<RangeMap> maps = noisySphere(0.01);
  ReconstructionOptions given = smallOptions();
  given.dataTerm = DataTermSource::kGrids;
  const ReconstructionSettings settings = resolveReconstructionSettings(given, ScanSummary(maps));
  Fusion fusion(fusionSettingsOf(settings));
  for (const RangeMap& map : maps) fusion.integrate(map);
  EXPECT_NO_THROW(Reconstructor(fusion, settings));
  for (const auto& spoil : std::vector<std::function<void(ReconstructionSettings&)>>{
           [](ReconstructionSettings& s) { s.voxelSize *= 2.0; }, [](ReconstructionSettings& s) { s.levels = 1; },
           [](ReconstructionSettings& s) { s.epsilon *= 2.0; },
           [](ReconstructionSettings& s) { s.window = WindowKind::kBinary; },
           [](ReconstructionSettings& s) { s.dataTerm = DataTermSource::kPerMap; }}) {
    ReconstructionSettings other = settings;
    spoil(other);
    EXPECT_THROW(Reconstructor(fusion, other), std::invalid_argument);
  }
}

TEST(Reconstructor, KeepsWhatItIsGivenAndRefusesWhatCannotBeUsed) {
  ReconstructionOptions given;
  given.voxelSize = 0.05;
  given.levels = 3;
  given.epsilon = 0.03;
  given.beta = 0.0;  // the prior off, not derived
  const Reconstructor r(noisySphere(0.01), given);
  const ReconstructionSettings& o = r.settings();
  EXPECT_EQ(o.voxelSize, 0.05);
  EXPECT_EQ(o.levels, 3);
  EXPECT_EQ(o.epsilon, 0.03);
  EXPECT_EQ(o.beta, 0.0);
  for (const auto& spoil : std::vector<std::function<void(ReconstructionOptions&)>>{
           [](ReconstructionOptions& b) { b.voxelSize = 0.0; }, [](ReconstructionOptions& b) { b.voxelSize = -0.1; },
           [](ReconstructionOptions& b) { b.levels = 0; }, [](ReconstructionOptions& b) { b.levels = 13; },
           [](ReconstructionOptions& b) { b.epsilon = 0.0; }, [](ReconstructionOptions& b) { b.beta = -1.0; },
           [](ReconstructionOptions& b) { b.beta = std::nan(""); }}) {
    ReconstructionOptions bad;
    spoil(bad);
    EXPECT_THROW(Reconstructor(noisySphere(0.01), bad), std::invalid_argument);
  }
  ReconstructionOptions bad;
  bad.patience = 0;
  EXPECT_THROW(Reconstructor(noisySphere(0.01), bad), std::invalid_argument);
}

TEST(Reconstructor, BeatsTheLinearSolutionOnNoisyData) {
  const double sigma = 0.08;  // two voxels
  const std::vector<RangeMap> maps = noisySphere(sigma);
  const Reconstructor r(maps, smallOptions());
  const ReconstructionResult result = r.run();
  const openvdb::FloatGrid& surface = *result.levelSet;
  EXPECT_EQ(surface.getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(surface.getName(), "surface");
  EXPECT_EQ(openvdb::tools::checkLevelSet(surface, 6), "");
  EXPECT_EQ(insideComponents(surface), 1);
  EXPECT_NEAR(surface.metaValue<double>("levelfuse_voxel_size"), 0.04, 1e-12);
  EXPECT_EQ(surface.metaValue<int>("levelfuse_scans"), 6);
  ASSERT_EQ(result.levels.size(), 2u);
  EXPECT_NEAR(result.levels[0].voxelSize, 0.08, 1e-12);
  for (const LevelReport& level : result.levels) EXPECT_TRUE(level.converged || level.settled);

  // The linear solution on the same data and grid, for comparison.
  const ForceField force(maps, r.forceOptions(1));
  const auto linear = force.linearSolution(0.04);
  const double linearRms = rmsOver(zeroCrossings(*linear), kSphere);
  const double rms = rmsOver(zeroCrossings(surface), kSphere);
  RecordProperty("rms_linear_over_sigma", std::to_string(linearRms / sigma));
  RecordProperty("rms_over_sigma", std::to_string(rms / sigma));
  EXPECT_LT(rms, 0.7 * linearRms);
  EXPECT_LT(rms, 0.25 * sigma);
}

TEST(Reconstructor, SphericalScansOfASphere) {
  // Six region scans by spherical scanners whose noise grows with range.
  synth::SceneOptions scan;
  scan.scanner = RangeMap::Kind::kSpherical;
  scan.resolution = 120;
  scan.noise = 0.02;  // of the diameter at the scanners' distance from the centre: 0.04
  const synth::Scene scene = synth::analyticScene(synth::standardShape(shapes::AnalyticShape::Kind::kSphere), scan);
  const Reconstructor r(scene.maps, smallOptions());
  // Spherical scanners are stations: a scene's defaults (one grid, no prior), even around an object.
  EXPECT_TRUE(r.summary().aScene());
  const ReconstructionResult result = r.run();
  EXPECT_EQ(openvdb::tools::checkLevelSet(*result.levelSet, 6), "");
  EXPECT_EQ(insideComponents(*result.levelSet), 1);
  const ForceField force(scene.maps, r.forceOptions(1));
  const double linearRms = rmsOver(zeroCrossings(*force.linearSolution(0.04)), *scene.truth);
  const double rms = rmsOver(zeroCrossings(*result.levelSet), *scene.truth);
  RecordProperty("rms_linear_over_sigma", std::to_string(linearRms / scene.noiseSigma));
  RecordProperty("rms_over_sigma", std::to_string(rms / scene.noiseSigma));
  EXPECT_LT(rms, linearRms);
  EXPECT_LT(rms, 0.3 * scene.noiseSigma);
}

TEST(Reconstructor, TheRoomFromThreeTripods) {
  // A scene seen from inside by spherical scanners: what they saw comes back
  // within a fraction of a voxel of the true room.
  synth::SceneOptions scan;
  scan.resolution = 100;  // 0.9 degree steps: 4.7 cm between rays 3 m away
  scan.noise = 0.0004;    // 1 mm per metre of range
  const synth::Scene scene = synth::roomScene(shapes::Room{}, scan);
  ReconstructionOptions options;
  options.voxelSize = 0.05;
  const Reconstructor r(scene.maps, options);
  EXPECT_TRUE(r.summary().aScene());
  const ReconstructionResult result = r.run();
  EXPECT_EQ(openvdb::tools::checkLevelSet(*result.levelSet, 6), "");
  ASSERT_TRUE(result.weight);
  // The surface the scanners saw (the level set also closes the walls'
  // solid from behind, where no scanner looked).
  const std::vector<Vec3d> seen = zeroCrossingsShown(*result.levelSet, result.weight.get());
  EXPECT_LT(seen.size(), zeroCrossings(*result.levelSet).size());
  const double rms = rmsOver(seen, *scene.truth);
  RecordProperty("rms_seen_over_voxel", std::to_string(rms / 0.05));
  EXPECT_LT(rms, 0.2 * 0.05);
  // Every wall, the floor and the ceiling come back: points of them (not
  // under the table nor in the pillar) lie within half a voxel of the surface.
  const shapes::Room& room = scene.truth->room;
  std::vector<Vec3d> onTheRoom;
  for (double a = 0.05; a < 1.0; a += 0.1)
    for (double b = 0.05; b < 1.0; b += 0.1) {
      const Vec3d s = room.size;
      for (const Vec3d& p : {Vec3d((a - 0.5) * s.x(), (b - 0.5) * s.y(), 0.0), Vec3d((a - 0.5) * s.x(), (b - 0.5) * s.y(), s.z()),
                             Vec3d(-0.5 * s.x(), (a - 0.5) * s.y(), b * s.z()), Vec3d(0.5 * s.x(), (a - 0.5) * s.y(), b * s.z()),
                             Vec3d((a - 0.5) * s.x(), -0.5 * s.y(), b * s.z()), Vec3d((a - 0.5) * s.x(), 0.5 * s.y(), b * s.z())})
        if (std::fabs(room(p)) < 1e-9) onTheRoom.push_back(p);
    }
  ASSERT_GT(onTheRoom.size(), 500u);
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi(*result.levelSet);
  std::size_t near = 0;
  for (const Vec3d& p : onTheRoom) near += std::fabs(phi.wsSample(p)) < 0.5 * 0.05;
  EXPECT_GT(near, 0.97 * onTheRoom.size()) << near << " of " << onTheRoom.size();
}

TEST(Reconstructor, ChoosesTheDataTermByTheNumberOfScans) {
  EXPECT_EQ(Reconstructor(noisySphere(0.01)).settings().dataTerm, DataTermSource::kPerMap);
  std::vector<RangeMap> many;
  for (int copy = 0; copy <= static_cast<int>(kGridsFromScans) / 6; ++copy)
    for (RangeMap& m : noisySphere(0.01, static_cast<std::uint64_t>(1 + 6 * copy))) many.push_back(std::move(m));
  ASSERT_GT(many.size(), kGridsFromScans);
  EXPECT_EQ(Reconstructor(many).settings().dataTerm, DataTermSource::kGrids);
  ReconstructionOptions chosen;
  chosen.dataTerm = DataTermSource::kGrids;
  EXPECT_EQ(Reconstructor(noisySphere(0.01), chosen).settings().dataTerm, DataTermSource::kGrids);
}

TEST(Reconstructor, GridsAndPerMapTermsReachTheSameSurface) {
  // The same noisy sphere with the data term sampled from grids and
  // evaluated per map: the two surfaces lie as close to the sphere (within
  // 10%) and a small part of a voxel from each other.
  const double sigma = 0.08;
  const std::vector<RangeMap> maps = noisySphere(sigma);
  ReconstructionOptions options = smallOptions();
  options.dataTerm = DataTermSource::kPerMap;
  const ReconstructionResult perMap = Reconstructor(maps, options).run();
  options.dataTerm = DataTermSource::kGrids;
  const ReconstructionResult grids = Reconstructor(maps, options).run();
  EXPECT_EQ(grids.levelSet->metaValue<std::string>("levelfuse_data_term"), "grids");
  EXPECT_EQ(perMap.levelSet->metaValue<std::string>("levelfuse_data_term"), "maps");
  const double rmsPerMap = rmsOver(zeroCrossings(*perMap.levelSet), kSphere);
  const double rmsGrids = rmsOver(zeroCrossings(*grids.levelSet), kSphere);
  RecordProperty("rms_per_map_over_sigma", std::to_string(rmsPerMap / sigma));
  RecordProperty("rms_grids_over_sigma", std::to_string(rmsGrids / sigma));
  EXPECT_LT(rmsGrids, 1.1 * rmsPerMap);
  EXPECT_LT(rmsGrids, 0.25 * sigma);
  EXPECT_EQ(insideComponents(*grids.levelSet), 1);
  // Both return the surface's weight on its band; six views saw all of the sphere.
  for (const ReconstructionResult* result : {&perMap, &grids}) {
    ASSERT_TRUE(result->weight);
    EXPECT_TRUE(test::weighsTheBand(*result->weight, *result->levelSet));
    const auto mesh = meshFromLevelSet(*result->levelSet);
    EXPECT_EQ(trimMesh(mesh, *result->weight, kObservedWeight).triangleCount(), mesh.triangleCount());
  }
}

TEST(Reconstructor, TakesReadingsThatLieInOnePlane) {
  // A depth frame facing a wall square on: every reading at 1 m, a box of no
  // volume, which was taken for no readings at all.
  std::vector<RangeMap> maps{RangeMap::pinhole(32, 32, std::vector<float>(32 * 32, 1.0f),
                                               PinholeProjection{30.0, 30.0, 16.0, 16.0},
                                               openvdb::math::Mat4d::identity(), 0.0015, "wall")};
  const Reconstructor wall(maps);
  EXPECT_DOUBLE_EQ(wall.bounds().extents().z(), 0.0);
  EXPECT_GT(wall.settings().voxelSize, 0.0);
  maps = {RangeMap::pinhole(2, 2, {1.0f, NAN, NAN, NAN}, PinholeProjection{30.0, 30.0, 0.0, 0.0},
                            openvdb::math::Mat4d::identity(), 0.0015, "point")};
  try {
    Reconstructor{maps};
    FAIL() << "one reading was taken for a surface";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("every reading lies at one point"), std::string::npos) << e.what();
  }
}

TEST(Reconstructor, RefusesAVoxelSizeThatWouldNotFitInMemory) {
  ReconstructionOptions options;
  options.voxelSize = 0.005;  // 400 voxels across: about 0.5 million on the surface, some 200 MiB
  options.memoryBudget = MemoryBudget(64u << 20);
  {
    const Reconstructor tooFine(noisySphere(0.01), options);
    try {
      tooFine.run();
      FAIL() << "the reconstruction ran";
    } catch (const InsufficientMemory& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("a voxel size of 0.005 (about 0."), std::string::npos) << message;
      EXPECT_THROW(tooFine.linearSolution(), InsufficientMemory);  // the linear solution alone, too
      const std::size_t at = message.find("voxel size of at least ");
      ASSERT_NE(at, std::string::npos) << message;
      // The advice fits: memory follows the surface's area.
      const double advised = std::stod(message.substr(at + 23));
      EXPECT_GT(advised, 0.005 * std::sqrt(2.0)) << message;
      EXPECT_LT(advised, 0.005 * 4.0) << message;
      options.voxelSize = advised;
      options.levels.reset();
      options.minIterations = 1;
      options.maxIterations = 1;
      EXPECT_NO_THROW(Reconstructor(noisySphere(0.01), options).run());
    }
  }
  // Too many voxels for the initial model: more grids are the fix.
  options = ReconstructionOptions();
  options.voxelSize = 0.002;
  options.levels = 1;
  options.memoryBudget = MemoryBudget(1u << 20);
  const Reconstructor oneFineGrid(noisySphere(0.01), options);
  for (const bool linear : {false, true}) {
    try {
      if (linear) oneFineGrid.linearSolution();
      else oneFineGrid.run();
      FAIL() << "the reconstruction ran";
    } catch (const InsufficientMemory& e) {
      EXPECT_NE(std::string(e.what()).find("use more grids"), std::string::npos) << e.what();
    }
  }
}

TEST(Reconstructor, ReportsProgressAndCanBeCancelled) {
  const Reconstructor r(noisySphere(0.01), smallOptions());
  std::vector<ReconstructionProgress> seen;
  r.run([&](const ReconstructionProgress& p) {
    seen.push_back(p);
    return true;
  });
  ASSERT_GT(seen.size(), 5u);
  EXPECT_EQ(seen.front().stage, ReconstructionProgress::Stage::kInitialModel);
  EXPECT_EQ(seen.back().stage, ReconstructionProgress::Stage::kDone);
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GE(seen[i].level, seen[i - 1].level);
    EXPECT_GE(seen[i].seconds, seen[i - 1].seconds);
  }
  int calls = 0;
  EXPECT_THROW(r.run([&](const ReconstructionProgress&) { return ++calls < 4; }), ReconstructionCancelled);
  EXPECT_EQ(calls, 4);
}

TEST(Reconstructor, ReportsEachScanIntegratedIntoTheGrids) {
  ReconstructionOptions options = smallOptions();
  options.dataTerm = DataTermSource::kGrids;
  const Reconstructor r(noisySphere(0.01), options);
  const std::size_t scans = r.maps().size();
  ASSERT_GT(scans, 1u);
  ASSERT_GT(*options.levels, 1);
  // Scans 1, 2, ..., all of them, in order, once for every grid at once,
  // before the first grid's first iteration; none after.
  std::vector<std::size_t> integrated;
  int firstIteration = -1, calls = 0;
  r.run([&](const ReconstructionProgress& p) {
    ++calls;
    if (p.stage == ReconstructionProgress::Stage::kIntegrating) {
      EXPECT_EQ(p.scans, scans);
      EXPECT_EQ(p.level, 0);
      EXPECT_EQ(firstIteration, -1) << "integrating after the evolution began";
      integrated.push_back(p.scan);
    }
    if (p.stage == ReconstructionProgress::Stage::kEvolving && firstIteration < 0) firstIteration = calls;
    return true;
  });
  std::vector<std::size_t> expected(scans);
  for (std::size_t i = 0; i < scans; ++i) expected[i] = i + 1;
  EXPECT_EQ(integrated, expected);
  EXPECT_GT(firstIteration, 0);
  // The initial model: carving asks every scan twice, each reported, with the
  // data term from grids or from the maps.
  for (const DataTermSource source : {DataTermSource::kGrids, DataTermSource::kPerMap}) {
    ReconstructionOptions o = smallOptions();
    o.dataTerm = source;
    std::vector<std::size_t> carved;
    Reconstructor(noisySphere(0.01), o).run([&](const ReconstructionProgress& p) {
      if (p.stage == ReconstructionProgress::Stage::kInitialModel && p.scan > 0) {
        EXPECT_EQ(p.scans, scans);
        carved.push_back(p.scan);
      }
      return true;
    });
    std::vector<std::size_t> twice = expected;
    twice.insert(twice.end(), expected.begin(), expected.end());
    EXPECT_EQ(carved, twice);
  }
  // A cancel while integrating stops the run there.
  ReconstructionProgress last;
  EXPECT_THROW(r.run([&](const ReconstructionProgress& p) {
    last = p;
    return p.stage != ReconstructionProgress::Stage::kIntegrating || p.scan < 2;
  }), ReconstructionCancelled);
  EXPECT_EQ(last.stage, ReconstructionProgress::Stage::kIntegrating);
  EXPECT_EQ(last.level, 0);
  EXPECT_EQ(last.scan, 2u);
}

/// The linear solution asks its interrupter while it works, not only before:
/// an interrupter that says stop at its n-th call stops it mid-way.
TEST(Reconstructor, TheLinearSolutionStopsWhenItsInterrupterSaysSo) {
  const Reconstructor r(noisySphere(0.01), smallOptions());
  std::atomic<int> calls{0};
  ASSERT_TRUE(r.linearSolution([&] { return ++calls < 0; }));  // never stops: counts the questions
  const int asked = calls.load();
  ASSERT_GT(asked, 10);
  calls = 0;
  EXPECT_THROW(r.linearSolution([&] { return ++calls >= asked / 2; }), Interrupted);
  calls = 0;
  EXPECT_THROW(r.run({}, [&] { return ++calls >= 3; }), Interrupted);  // in the initial model
}

TEST(Reconstructor, OneAndTwoThreadsGiveIdenticalSurfaces) {
  const Reconstructor r(noisySphere(0.02), smallOptions());
  openvdb::FloatGrid::Ptr one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = r.run().levelSet;
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = r.run().levelSet;
  }
  std::string why;
  EXPECT_TRUE(test::identical(*one, *two, &why)) << why;
}

}  // namespace
}  // namespace levelfuse

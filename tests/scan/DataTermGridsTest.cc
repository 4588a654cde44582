// The data term on grids binned by line of sight, against the per-map
// evaluation of Eqs. 17 and 37 (ForceField).

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/recon/DataSpeed.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/SightBins.h>
#include <levelfuse/synth/Synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

DataTermGrids gridsOf(const std::vector<RangeMap>& maps, double voxel, const ForceFieldOptions& options,
                      std::size_t grain = 1) {
  DataTermGrids grids(voxel, options.dataWindow(), options.positionVariance, grain);
  for (const RangeMap& m : maps) grids.integrate(m);
  return grids;
}

ForceFieldOptions optionsFor(double voxel, double epsilon) {
  ForceFieldOptions options;
  options.epsilon = epsilon;
  options.positionVariance = voxel * voxel / 120.0;
  return options;
}

TEST(SightBins, EveryDirectionIsNearItsBin) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  double worst = 1.0;
  for (int i = 0; i < 20000; ++i) {
    Vec3d d(normal(random), normal(random), normal(random));
    d.normalize();
    const int b = sightBin(d);
    worst = std::min(worst, d.dot(sightBinCentres()[static_cast<std::size_t>(b)]));
    for (const Vec3d& c : sightBinCentres()) ASSERT_LE(d.dot(c), d.dot(sightBinCentres()[static_cast<std::size_t>(b)]));
  }
  // The Voronoi cells of the icosahedron's vertices reach 37.38 degrees.
  EXPECT_GT(worst, std::cos(37.5 * M_PI / 180.0));
  EXPECT_LT(worst, std::cos(35.0 * M_PI / 180.0));
}

TEST(SightBins, ARoundConesBinIsTheBinOfEveryDirectionInIt) {
  // Round cones around random axes, narrow and wide: where
  // sightBinOfRoundCone names a bin, every direction within the cone (on its
  // rim, and inside) is in it; where directions of the cone lie in different
  // bins it names none.
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int named = 0, unnamed = 0;
  for (int cone = 0; cone < 4000; ++cone) {
    const Vec3d axis = Vec3d(normal(random), normal(random), normal(random)).unit();
    const double halfAngle = cone % 2 ? 0.02 : 0.3;
    const int bin = sightBinOfRoundCone(axis, std::sin(halfAngle));
    // Directions at the half angle (and within it) around the axis.
    const Vec3d across = axis.cross(std::fabs(axis.x()) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0)).unit();
    const Vec3d other = axis.cross(across);
    bool split = false;
    std::vector<Vec3d> directions;
    for (int i = 0; i < 64; ++i) {
      const double turn = 2.0 * M_PI * unit(random), angle = halfAngle * (i % 2 ? 1.0 : unit(random));
      const Vec3d sideways = across * std::cos(turn) + other * std::sin(turn);
      directions.push_back(axis * std::cos(angle) + sideways * std::sin(angle));
      split = split || sightBin(directions.back()) != sightBin(axis);
    }
    if (split) {
      EXPECT_EQ(bin, -1);
      ++unnamed;
      continue;
    }
    if (bin < 0) continue;
    ++named;
    for (const Vec3d& d : directions) ASSERT_EQ(sightBin(d), bin);
  }
  EXPECT_GT(named, 1000);
  EXPECT_GT(unnamed, 100);
  // No cone round a centre or wider than a half turn.
  EXPECT_EQ(sightBinOfRoundCone(sightBinCentres()[0], 1.0), -1);
  EXPECT_EQ(sightBinOfRoundCone(sightBinCentres()[0], std::nan("")), -1);
  EXPECT_EQ(sightBinOfRoundCone(sightBinCentres()[0], 0.0), 0);
}

TEST(DataTermGrids, NoTermReachesABoxItSaysHoldsNone) {
  // Boxes of 1 to 20 voxels around a scanned sphere: where the grids say no
  // term reaches a box, no point of it has a term in any direction, and the
  // answer is no for boxes away from the surface.
  const double voxel = 0.02;
  std::vector<RangeMap> maps;
  for (const Vec3d& direction : {Vec3d(0, 0, -1), Vec3d(1, 0, 0)})
    maps.push_back(synth::renderDistanceFunction([](const Vec3d& p) { return p.length() - 0.5; },
                                                 synth::orthographicView(direction, Vec3d(0.0), 1.4, 90),
                                                 synth::Noise{}, 0.005));
  const DataTermGrids grids = gridsOf(maps, voxel, optionsFor(voxel, 0.03));
  std::mt19937 random(5);
  std::uniform_real_distribution<double> position(-0.8, 0.8), size(voxel, 20 * voxel), unit(0.0, 1.0);
  int none = 0, some = 0;
  for (int b = 0; b < 3000; ++b) {
    const Vec3d lo(position(random), position(random), position(random));
    const openvdb::BBoxd box(lo, lo + Vec3d(size(random), size(random), size(random)));
    if (grids.mayHaveTermsIn(box)) {
      ++some;
      continue;
    }
    ++none;
    for (int i = 0; i < 20; ++i) {
      const Vec3d x = box.min() + (box.max() - box.min()) * Vec3d(unit(random), unit(random), unit(random));
      ASSERT_EQ(grids.weight(x), 0.0) << x;
      for (const Vec3d& n : {Vec3d(0, 0, 1), Vec3d(0, 0, -1), Vec3d(1, 0, 0), Vec3d(-1, 0, 0)})
        ASSERT_EQ(grids.facingTerms(x, n).weight, 0.0) << x;
    }
  }
  EXPECT_GT(none, 500);
  EXPECT_GT(some, 500);
  EXPECT_TRUE(grids.mayHaveTermsIn(openvdb::BBoxd(Vec3d(-0.01, -0.01, 0.49), Vec3d(0.01, 0.01, 0.51))));
  EXPECT_FALSE(grids.mayHaveTermsIn(openvdb::BBoxd(Vec3d(-0.05), Vec3d(0.05))));
}

TEST(DataTermGrids, OneScanOfAPlaneGivesItsDistanceBetweenVoxels) {
  // A tilted plane seen from above: D is linear, and the term carried along
  // grad D gives D itself at any point between voxels.
  const Vec3d normal = Vec3d(0.2, -0.1, 1.0).unit();
  const synth::View view = synth::orthographicView(Vec3d(0, 0, -1), Vec3d(0.0), 2.0, 100);
  const RangeMap map =
      synth::renderDistanceFunction([&](const Vec3d& p) { return p.dot(normal); }, view, synth::Noise{}, 0.01);
  const double voxel = 0.05;
  const ForceFieldOptions options = optionsFor(voxel, 0.1);
  const ForceField exact({map}, options);
  const DataTermGrids grids = gridsOf({map}, voxel, options);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> across(-0.5, 0.5), depth(-0.12, 0.12);
  for (int i = 0; i < 200; ++i) {
    const Vec3d onPlane(across(random), across(random), 0.0);
    const Vec3d x = onPlane - Vec3d(0, 0, onPlane.dot(normal) / normal.z()) + normal * depth(random);
    const DataTerms want = exact.facingTerms(x, normal), got = grids.facingTerms(x, normal);
    ASSERT_GT(want.weight, 0.0);
    // The weighted mean distance, the force of the evolution, to 1e-3 voxels.
    EXPECT_NEAR(got.g / got.weight, want.g / want.weight, 1e-3 * voxel) << x;
    EXPECT_NEAR(got.weight, want.weight, 0.05 * want.weight) << x;
    // Seen from the other side, nothing (Eq. 37).
    EXPECT_EQ(grids.facingTerms(x, -normal).weight, 0.0);
  }
}

TEST(DataTermGrids, BothSidesOfAThinWallStayApart) {
  // A slab 0.04 thick seen from above and from below: each face sees only
  // the scan of its own side, as Eq. 37 asks.
  const auto slab = [](const Vec3d& p) { return std::fabs(p.z()) - 0.02; };
  std::vector<RangeMap> maps;
  for (double sign : {-1.0, 1.0})
    maps.push_back(synth::renderDistanceFunction(
        slab, synth::orthographicView(Vec3d(0, 0, sign), Vec3d(0.0), 2.0, 80), synth::Noise{}, 0.005));
  const double voxel = 0.02;
  const DataTermGrids grids = gridsOf(maps, voxel, optionsFor(voxel, 0.03));
  for (double z : {0.015, 0.02, 0.027}) {
    const DataTerms top = grids.facingTerms(Vec3d(0.1, 0.1, z), Vec3d(0, 0, 1));
    EXPECT_NEAR(top.g / top.weight, 0.02 - z, 1e-4) << z;  // D > 0 below the top face
    const DataTerms bottom = grids.facingTerms(Vec3d(0.1, 0.1, -z), Vec3d(0, 0, -1));
    EXPECT_NEAR(bottom.g / bottom.weight, 0.02 - z, 1e-4) << z;
  }
}

TEST(DataTermGrids, TorusForceMatchesThePerMapTerm) {
  const shapes::Torus torus{Vec3d(0.011, 0.017, -0.013), 1.0, 0.4};
  std::vector<RangeMap> maps;
  for (const synth::View& v : synth::ringViews(Vec3d(0.0), 3.2, 200, 6, 45.0))
    maps.push_back(synth::renderDistanceFunction(torus, v, synth::Noise{}, 0.01));
  const double voxel = 0.04;
  const ForceFieldOptions options = optionsFor(voxel, voxel);
  const ForceField exact(maps, options);
  const DataTermGrids grids = gridsOf(maps, voxel, options);
  const DataForce<ForceField> exactForce{&exact};
  const DataForce<DataTermGrids> gridForce{&grids};
  std::mt19937 random(11);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI), offset(-0.5 * voxel, 0.5 * voxel);
  double sumError = 0.0, sumReadingsError = 0.0;
  std::vector<double> errors;
  int compared = 0, disagree = 0;
  for (int i = 0; i < 2000; ++i) {
    const double u = angle(random), v = angle(random);
    const Vec3d n(std::cos(u) * std::cos(v), std::sin(u) * std::cos(v), std::sin(v));
    const Vec3d x = torus.centre + Vec3d(std::cos(u), std::sin(u), 0.0) * 1.0 + n * (0.4 + offset(random));
    const DataTerms want = exact.facingTerms(x, n), got = grids.facingTerms(x, n);
    if ((want.weight > 0.0) != (got.weight > 0.0)) ++disagree;
    if (!(want.weight > 0.0)) continue;
    const double fWant = exactForce(x, n), fGot = gridForce(x, n);
    sumError += std::fabs(fGot - fWant);
    sumReadingsError += std::fabs(std::min(1.0, got.readings) - std::min(1.0, want.readings));
    errors.push_back(std::fabs(fGot - fWant) / voxel);
    ++compared;
  }
  ASSERT_GT(compared, 1500);
  EXPECT_LT(disagree, 20);
  // Within half a voxel of the surface the force differs from the per-map one
  // by a few hundredths of a voxel (measured: mean 0.031, median 0.023, p99
  // 0.14; the curvature of the readings between voxels). Without carrying the
  // terms along grad D the median would be 0.13 voxels.
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(sumError / compared, 0.04 * voxel);
  // The readings that reach x, from one reading's weight per leaf, where they
  // act: the fading min(1, N) of the force.
  EXPECT_LT(sumReadingsError / compared, 0.05) << sumReadingsError / compared;
  EXPECT_LT(errors[errors.size() / 2], 0.03);
  EXPECT_LT(errors[errors.size() * 99 / 100], 0.2);
}

TEST(DataTermGrids, SumsAreThoseOfThePerMapAccumulation) {
  const shapes::Sphere sphere{Vec3d(0.013, -0.021, 0.007), 1.0};
  std::vector<RangeMap> maps;
  for (const synth::View& v : synth::sixAxisViews(Vec3d(0.0), 2.4, 100))
    maps.push_back(synth::renderDistanceFunction(sphere, v, synth::Noise{}, 0.02));
  const double voxel = 0.05;
  const ForceFieldOptions options = optionsFor(voxel, voxel);
  const AccumulatedField want = ForceField(maps, options).accumulate(voxel);
  const DataTermGrids grids = gridsOf(maps, voxel, options);
  const openvdb::FloatGrid::Ptr g = grids.gGrid(), w = grids.weightGrid();
  EXPECT_EQ(w->activeVoxelCount(), want.weight->activeVoxelCount());
  EXPECT_EQ(grids.mapCount(), maps.size());
  const auto acc = want.weight->getConstAccessor();
  const auto gAcc = want.g->getConstAccessor();
  for (auto it = w->cbeginValueOn(); it; ++it) {
    ASSERT_NEAR(*it, acc.getValue(it.getCoord()), 1e-5 * acc.getValue(it.getCoord()));
    ASSERT_NEAR(g->tree().getValue(it.getCoord()), gAcc.getValue(it.getCoord()), 1e-5 * acc.getValue(it.getCoord()) * voxel);
  }
}

TEST(DataTermGrids, AMapReachingManyBatchesOfLeavesGivesThePerMapSums) {
  // One view of a sphere on a fine grid: its windows reach leaves enough for
  // several batches, whose sums must be one pass's.
  const shapes::Sphere sphere{Vec3d(0.013, -0.021, 0.007), 1.0};
  const std::vector<RangeMap> maps{
      synth::renderDistanceFunction(sphere, synth::sixAxisViews(Vec3d(0.0), 2.4, 320).front(), synth::Noise{}, 0.02)};
  const double voxel = 0.006;
  const ForceFieldOptions options = optionsFor(voxel, 2.0 * voxel);
  const AccumulatedField want = ForceField(maps, options).accumulate(voxel);
  const DataTermGrids grids = gridsOf(maps, voxel, options);
  const openvdb::FloatGrid::Ptr g = grids.gGrid(), w = grids.weightGrid();
  EXPECT_GT(w->tree().leafCount(), 2 * DataTermGrids::kLeavesPerBatch);
  EXPECT_EQ(w->activeVoxelCount(), want.weight->activeVoxelCount());
  const auto acc = want.weight->getConstAccessor();
  const auto gAcc = want.g->getConstAccessor();
  for (auto it = w->cbeginValueOn(); it; ++it) {
    ASSERT_NEAR(*it, acc.getValue(it.getCoord()), 1e-5 * acc.getValue(it.getCoord()));
    ASSERT_NEAR(g->tree().getValue(it.getCoord()), gAcc.getValue(it.getCoord()), 1e-5 * acc.getValue(it.getCoord()) * voxel);
  }
}

TEST(DataTermGrids, OneAndTwoThreadsGiveTheSameGrids) {
  const shapes::Sphere sphere{Vec3d(0.0), 1.0};
  std::vector<RangeMap> maps;
  for (const synth::View& v : synth::viewsAround(Vec3d(0.0), 2.4, 80, 7))
    maps.push_back(synth::renderDistanceFunction(sphere, v, synth::Noise{}, 0.02));
  const ForceFieldOptions options = optionsFor(0.05, 0.05);
  const DataTermGrids serial = gridsOf(maps, 0.05, options, 0), parallel = gridsOf(maps, 0.05, options, 1);
  const openvdb::FloatGrid::Ptr a = serial.gGrid(), b = parallel.gGrid();
  ASSERT_EQ(a->activeVoxelCount(), b->activeVoxelCount());
  for (auto it = a->cbeginValueOn(); it; ++it) ASSERT_EQ(*it, b->tree().getValue(it.getCoord()));
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(-1.1, 1.1);
  for (int i = 0; i < 500; ++i) {
    const Vec3d x(coordinate(random), coordinate(random), coordinate(random)), n = x.unitSafe();
    ASSERT_EQ(serial.facingTerms(x, n).g, parallel.facingTerms(x, n).g);
  }
}

TEST(DataTermGrids, ASlabOfTheGridsHoldsTheWholeGridsSumsThere) {
  const shapes::Sphere sphere{Vec3d(0.013, -0.021, 0.007), 1.0};
  std::vector<RangeMap> maps;
  for (const synth::View& v : synth::viewsAround(Vec3d(0.0), 2.4, 80, 7))
    maps.push_back(synth::renderDistanceFunction(sphere, v, synth::Noise{}, 0.02));
  const double voxel = 0.05;
  const ForceFieldOptions options = optionsFor(voxel, voxel);
  const DataTermGrids whole = gridsOf(maps, voxel, options);
  // The slab of leaf columns x = 0 and 8: world x in [-0.025, 0.775).
  DataTermGrids slab(voxel, options.dataWindow(), options.positionVariance);
  slab.restrictToSlab(0, 16);
  for (const RangeMap& m : maps) slab.integrate(m);
  const openvdb::FloatGrid::Ptr g = whole.gGrid(), w = whole.weightGrid();
  const openvdb::FloatGrid::Ptr slabG = slab.gGrid(), slabW = slab.weightGrid();
  std::size_t inside = 0;
  for (auto it = w->cbeginValueOn(); it; ++it) {
    const openvdb::Coord ijk = it.getCoord();
    if (ijk.x() < 0 || ijk.x() >= 16) continue;
    ++inside;
    ASSERT_TRUE(slabW->tree().isValueOn(ijk)) << ijk;
    ASSERT_EQ(*it, slabW->tree().getValue(ijk)) << ijk;
    ASSERT_EQ(g->tree().getValue(ijk), slabG->tree().getValue(ijk)) << ijk;
  }
  EXPECT_GT(inside, 1000u);
  EXPECT_EQ(slabW->activeVoxelCount(), inside) << "the slab holds terms outside its columns";
  // The facing-checked term wherever its voxels and leaf lie in the slab.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> across(0.02, 0.72), coordinate(-1.1, 1.1);
  for (int i = 0; i < 500; ++i) {
    const Vec3d x(across(random), coordinate(random), coordinate(random)), n = x.unitSafe();
    const DataTerms a = whole.facingTerms(x, n), b = slab.facingTerms(x, n);
    ASSERT_EQ(a.g, b.g) << x;
    ASSERT_EQ(a.weight, b.weight) << x;
    ASSERT_EQ(a.readings, b.readings) << x;
  }
  EXPECT_THROW(slab.restrictToSlab(8, 8), std::invalid_argument);
}

TEST(DataTermGrids, RejectsUnusableSettings) {
  const DataWindow window(WindowKind::kGaussian, 0.1, 3.0);
  EXPECT_THROW(DataTermGrids(0.0, window, 0.0), std::invalid_argument);
  EXPECT_THROW(DataTermGrids(std::nan(""), window, 0.0), std::invalid_argument);
  EXPECT_THROW(DataTermGrids(0.1, window, -1.0), std::invalid_argument);
  EXPECT_THROW(DataWindow(WindowKind::kGaussian, 0.0, 3.0), std::invalid_argument);
  EXPECT_THROW(DataWindow(WindowKind::kGaussian, 0.1, std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse

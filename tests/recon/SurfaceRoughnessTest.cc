// The roughness ruler on surfaces of known curvature.

#include "support/TestSupport.h"

#include <levelfuse/recon/SurfaceRoughness.h>

#include <openvdb/tools/LevelSetPlatonic.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <tbb/global_control.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

using test::pointsOnSphere;

class SurfaceRoughnessTest : public ::testing::Test {
 protected:
  const Vec3d centre{0.1, -0.2, 0.05};
  const double radius = 1.0;
  // A sphere of radius 1 meshed from a level set of 0.04 (25 voxels in radius).
  TriangleMesh sphere = meshFromLevelSet(
      *openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(centre), 0.04f, 3.0f));
};

TEST_F(SurfaceRoughnessTest, ASphereMeasuresTheInverseOfItsRadius) {
  const SurfaceRoughness r = measureRoughness(sphere, pointsOnSphere(centre, radius, 2000, 3), 0.02, 0.1);
  EXPECT_EQ(r.readings, 2000u);
  EXPECT_NEAR(r.medianAbsolute, 1.0 / radius, 0.03 / radius);
  // The mesh's flat facets and their creases, seen by a ruler finer than they
  // are, spread H about its mean and lift the rms a little.
  EXPECT_GT(r.rms, 0.99 / radius);
  EXPECT_LT(r.rms, 1.12 / radius);
  // Points off the surface are measured where they project onto it.
  const SurfaceRoughness off = measureRoughness(sphere, pointsOnSphere(centre, radius + 0.06, 2000, 3), 0.02, 0.1);
  EXPECT_NEAR(off.rms, r.rms, 0.02 / radius);
}

TEST_F(SurfaceRoughnessTest, AFaceOfACubeIsFlat) {
  const TriangleMesh cube = meshFromLevelSet(*openvdb::tools::createLevelSetCube<openvdb::FloatGrid>(2.0f, openvdb::Vec3f(0.0f), 0.04f));
  std::vector<Vec3d> points;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j) points.emplace_back(0.05 * i, 0.05 * j, 1.0);  // the middle of the top face
  const SurfaceRoughness r = measureRoughness(cube, points, 0.02, 0.1);
  EXPECT_EQ(r.readings, points.size());
  EXPECT_LT(r.rms, 0.01);
}

TEST_F(SurfaceRoughnessTest, BumpsRaiseItAndStraysAreSkipped) {
  // The same sphere with each vertex moved along its radius by noise of a tenth of a voxel.
  TriangleMesh bumpy = sphere;
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 0.004);
  for (std::size_t v = 0; v < bumpy.vertexCount(); ++v) {
    Vec3d p(bumpy.xyz[3 * v], bumpy.xyz[3 * v + 1], bumpy.xyz[3 * v + 2]);
    p = centre + (p - centre).unit() * (radius + noise(random));
    for (int k = 0; k < 3; ++k) bumpy.xyz[3 * v + k] = static_cast<float>(p[k]);
  }
  std::vector<Vec3d> points = pointsOnSphere(centre, radius, 2000, 9);
  const SurfaceRoughness smooth = measureRoughness(sphere, points, 0.02, 0.1);
  const SurfaceRoughness rough = measureRoughness(bumpy, points, 0.02, 0.1);
  EXPECT_GT(rough.rms, 1.5 * smooth.rms);
  EXPECT_GT(rough.p90Absolute, smooth.p90Absolute);
  // A point half a radius away is out of reach.
  points.push_back(centre + Vec3d(0.0, 0.0, 1.5 * radius));
  EXPECT_EQ(measureRoughness(sphere, points, 0.02, 0.1).readings, 2000u);
}

TEST_F(SurfaceRoughnessTest, TheSameWithOneOrTwoThreads) {
  const std::vector<Vec3d> points = pointsOnSphere(centre, radius + 0.01, 3000, 13);
  SurfaceRoughness byThreads[2];
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    byThreads[threads - 1] = measureRoughness(sphere, points, 0.02, 0.1);
  }
  EXPECT_EQ(byThreads[0].readings, byThreads[1].readings);
  EXPECT_EQ(byThreads[0].rms, byThreads[1].rms);
  EXPECT_EQ(byThreads[0].medianAbsolute, byThreads[1].medianAbsolute);
  EXPECT_EQ(byThreads[0].p90Absolute, byThreads[1].p90Absolute);
}

TEST_F(SurfaceRoughnessTest, RejectsWhatItCannotMeasure) {
  const std::vector<Vec3d> points = pointsOnSphere(centre, radius, 10, 1);
  EXPECT_THROW(measureRoughness(TriangleMesh(), points, 0.02, 0.1), std::invalid_argument);
  EXPECT_THROW(measureRoughness(sphere, points, 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(measureRoughness(sphere, points, 0.02, -1.0), std::invalid_argument);
}

}  // namespace
}  // namespace levelfuse

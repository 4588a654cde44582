// The fit of a surface to points at known distances from it.

#include "support/TestSupport.h"

#include <levelfuse/recon/DataFit.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// Points on random directions around `centre`, `offset` outside a sphere of radius `radius`.
std::vector<Vec3d> pointsAround(const Vec3d& centre, double radius, double offset, int count, unsigned seed) {
  return test::pointsOnSphere(centre, radius + offset, count, seed);
}

class DataFitTest : public ::testing::Test {
 protected:
  const Vec3d centre{0.013, -0.021, 0.007};
  const double radius = 1.0, voxel = 0.02;  // 50 voxels in radius, a band of 3 voxels
  openvdb::FloatGrid::Ptr sphere =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, openvdb::Vec3f(centre), 0.02f, 3.0f);
};

TEST_F(DataFitTest, MeasuresDistancesInsideAndOutsideTheBand) {
  for (const double offset : {0.0, 0.013, -0.027, 0.045}) {  // up to 2.25 voxels
    const DataFit fit = measureDataFit(*sphere, pointsAround(centre, radius, offset, 500, 7));
    EXPECT_EQ(fit.readings, 500u);
    EXPECT_NEAR(fit.mean, std::fabs(offset), 0.01 * voxel) << offset;
    EXPECT_NEAR(fit.median, std::fabs(offset), 0.01 * voxel) << offset;
    EXPECT_EQ(fit.beyondBand, 0.0);
    EXPECT_EQ(fit.withinVoxel, std::fabs(offset) <= voxel ? 1.0 : 0.0);
  }
  // Beyond the band (3 voxels): measured to the surface all the same, and counted.
  for (const double offset : {0.1, -0.2, 0.5}) {
    const DataFit fit = measureDataFit(*sphere, pointsAround(centre, radius, offset, 300, 11));
    EXPECT_EQ(fit.beyondBand, 1.0) << offset;
    EXPECT_NEAR(fit.mean, std::fabs(offset), 0.1 * voxel) << offset;
    EXPECT_GE(fit.median, 3.0 * voxel) << offset;
  }
}

TEST_F(DataFitTest, SummarisesAMixture) {
  // 80% of the points on the surface, 20% half a radius out: mean 0.1, median 0, p90 0.5.
  std::vector<Vec3d> points = pointsAround(centre, radius, 0.0, 800, 3);
  const std::vector<Vec3d> far = pointsAround(centre, radius, 0.5, 200, 5);
  points.insert(points.end(), far.begin(), far.end());
  const DataFit fit = measureDataFit(*sphere, points);
  EXPECT_NEAR(fit.mean, 0.1, 0.02 * voxel);
  EXPECT_NEAR(fit.rms, std::sqrt(0.2 * 0.25), 0.02 * voxel);
  EXPECT_LT(fit.median, 0.01 * voxel);
  EXPECT_NEAR(fit.p90, 0.5, 0.1 * voxel);
  EXPECT_NEAR(fit.beyondBand, 0.2, 1e-12);
  EXPECT_NEAR(fit.withinVoxel, 0.8, 1e-12);
}

TEST_F(DataFitTest, MeasuresTheSamplesOfAResampledMap) {
  // A map whose readings lie on the sphere's top but whose samples (the points
  // it was resampled from) lie 0.03 outside: the fit is the samples'.
  const int n = 11;
  std::vector<float> readings;
  for (int v = 0; v < n; ++v)
    for (int u = 0; u < n; ++u) {
      const double x = 0.01 * (u - 5), y = 0.01 * (v - 5);
      readings.push_back(static_cast<float>(-std::sqrt(radius * radius - x * x - y * y)));  // from above, rays along -z
    }
  openvdb::math::Mat4d mapToWorld = openvdb::math::Mat4d::identity();
  mapToWorld.setToRotation(openvdb::math::X_AXIS, M_PI);  // the map's +z (away from the scanner) is the world's -z
  mapToWorld.setTranslation(centre);
  RangeMap map = RangeMap::orthographic(n, n, readings, OrthographicProjection{0.01, openvdb::math::Vec2d(-0.05)},
                                        mapToWorld, 0.001, "cap");
  std::vector<RangeMap> maps{map};
  EXPECT_EQ(measureDataFit(*sphere, maps).readings, std::size_t(n * n));
  EXPECT_LT(measureDataFit(*sphere, maps).mean, 0.01 * voxel);
  const std::vector<Vec3d> samples = pointsAround(centre, radius, 0.03, 40, 13);
  maps[0].setSamples(samples, 0.02);
  const DataFit fit = measureDataFit(*sphere, maps);
  EXPECT_EQ(fit.readings, 40u);
  EXPECT_NEAR(fit.mean, 0.03, 0.01 * voxel);
  EXPECT_EQ(measureDataFit(*sphere, maps, 2).readings, 10u);  // every 4th sample
  // Without its samples the map's fit is refused, not measured at its readings.
  maps[0].letSamplesGo();
  try {
    measureDataFit(*sphere, maps);
    ADD_FAILURE() << "the fit of a map whose samples were let go was measured";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'cap'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(fitStride(maps, 100), std::invalid_argument);
}

TEST_F(DataFitTest, TheStrideMeasuresAtMostTheGivenNumberOfPoints) {
  // Two 11 x 11 maps of valid readings: 242 points; stride 2 takes 6 x 6 of each, stride 3 4 x 4.
  std::vector<float> readings(121, 1.0f);
  const RangeMap map = RangeMap::orthographic(11, 11, readings, OrthographicProjection{0.01, openvdb::math::Vec2d(0.0)},
                                              openvdb::math::Mat4d::identity(), 0.001, "plane");
  const std::vector<RangeMap> maps{map, map};
  EXPECT_EQ(fitStride(maps, 1000), 1);
  EXPECT_EQ(fitStride(maps, 242), 1);
  EXPECT_EQ(fitStride(maps, 241), 2);
  EXPECT_EQ(fitStride(maps, 72), 2);
  EXPECT_EQ(fitStride(maps, 71), 3);
  EXPECT_EQ(measureDataFit(*sphere, maps, fitStride(maps, 71)).readings, 32u);
  EXPECT_THROW(fitStride(maps, 0), std::invalid_argument);
  // Maps visited one at a time are counted in one visit.
  int visits = 0;
  const RangeMapSequence once = [&](const RangeMapVisitor& visit) {
    ++visits;
    for (const RangeMap& m : maps) visit(m);
  };
  for (const std::size_t atMost : {1000u, 242u, 241u, 72u, 71u, 1u}) {
    visits = 0;
    EXPECT_EQ(fitStride(once, atMost), fitStride(maps, atMost)) << atMost;
    EXPECT_EQ(visits, 1);
  }
  EXPECT_EQ(fitStride(once, 1), kLargestFitStride);  // every stride measures a reading of each map: the largest
}

TEST_F(DataFitTest, MeasuresAMeshWithTheSameRuler) {
  // The sphere's zero set as triangles: points at known distances from it
  // measure the same as from the level set, inside the band and far beyond.
  const TriangleMesh mesh = meshFromLevelSet(*sphere);
  for (const double offset : {0.0, 0.013, -0.027, 0.3}) {
    const std::vector<Vec3d> points = pointsAround(centre, radius, offset, 500, 19);
    const DataFit fromMesh = measureDataFit(mesh, points);
    EXPECT_EQ(fromMesh.readings, 500u);
    EXPECT_NEAR(fromMesh.mean, std::fabs(offset), 0.01 * voxel) << offset;
    EXPECT_NEAR(fromMesh.median, std::fabs(offset), 0.01 * voxel) << offset;
    EXPECT_NEAR(fromMesh.mean, measureDataFit(*sphere, points).mean, 0.01 * voxel) << offset;
    EXPECT_EQ(fromMesh.withinVoxel, 0.0);  // a mesh has no voxel and no band
    EXPECT_EQ(fromMesh.beyondBand, 0.0);
  }
  EXPECT_EQ(measureDataFit(mesh, std::vector<Vec3d>{}).readings, 0u);
  EXPECT_THROW(measureDataFit(TriangleMesh{}, pointsAround(centre, radius, 0.0, 5, 1)), std::invalid_argument);
}

TEST_F(DataFitTest, RefusesWhatIsNotALevelSet) {
  openvdb::FloatGrid fog;
  fog.setGridClass(openvdb::GRID_FOG_VOLUME);
  EXPECT_THROW(measureDataFit(fog, std::vector<Vec3d>{Vec3d(0.0)}), std::invalid_argument);
  EXPECT_EQ(measureDataFit(*sphere, std::vector<Vec3d>{}).readings, 0u);
}

}  // namespace
}  // namespace levelfuse

// The data force of the MAP evolution: the readings' mean distance, whatever
// their depth and noise, fading where less than one reading reaches; the same
// rule from the per-map term and from the grids.

#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/recon/DataSpeed.h>

#include <openvdb/tools/LevelSetSphere.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kVoxel = 0.01;

/// `frames` depth frames of a wall square to the optical axis at `depth`,
/// with a depth camera's noise sigma(z) (io::DepthNoise's defaults).
std::vector<RangeMap> wallFrames(double depth, int frames) {
  io::DepthImage image;
  image.width = 64;
  image.height = 48;
  image.depth.assign(static_cast<std::size_t>(image.width * image.height), static_cast<float>(depth));
  PinholeProjection camera;
  camera.fx = camera.fy = 58.5;
  camera.cx = 32.0;
  camera.cy = 24.0;
  std::vector<RangeMap> maps;
  for (int i = 0; i < frames; ++i)
    maps.push_back(io::depthFrame(image, camera, openvdb::math::Mat4d::identity(), io::DepthNoise{}, "wall"));
  return maps;
}

ForceFieldOptions tenMillimetreGrid() {
  ForceFieldOptions options;
  options.epsilon = kVoxel;
  options.positionVariance = kVoxel * kVoxel / 120.0;
  return options;
}

/// The data term of `maps` from one of its two sources.
template <typename Field>
std::unique_ptr<Field> dataTermOf(const std::vector<RangeMap>& maps);

template <>
std::unique_ptr<ForceField> dataTermOf<ForceField>(const std::vector<RangeMap>& maps) {
  return std::make_unique<ForceField>(maps, tenMillimetreGrid());
}

template <>
std::unique_ptr<DataTermGrids> dataTermOf<DataTermGrids>(const std::vector<RangeMap>& maps) {
  const ForceFieldOptions options = tenMillimetreGrid();
  auto grids = std::make_unique<DataTermGrids>(kVoxel, options.dataWindow(), options.positionVariance);
  for (const RangeMap& map : maps) grids->integrate(map);
  return grids;
}

template <typename Field>
class DataForceTest : public ::testing::Test {};
using Sources = ::testing::Types<ForceField, DataTermGrids>;
TYPED_TEST_SUITE(DataForceTest, Sources);

TYPED_TEST(DataForceTest, IsTheMeanDistanceAtAnyDepth) {
  // Two frames: two readings reach every point near the wall. A surface 4 mm
  // behind the wall, facing the camera, moves 4 mm per unit time toward it,
  // at 1 m as at 3 m, where a reading weighs about a hundred times less.
  const Vec3d towardCamera(0.0, 0.0, -1.0);
  for (double depth : {1.0, 3.0}) {
    const auto field = dataTermOf<TypeParam>(wallFrames(depth, 2));
    const DataForce<TypeParam> force{field.get()};
    EXPECT_NEAR(force(Vec3d(0.0, 0.0, depth + 0.004), towardCamera), 0.004, 2e-4) << "wall at " << depth << " m";
    EXPECT_NEAR(force(Vec3d(0.0, 0.0, depth - 0.004), towardCamera), -0.004, 2e-4) << "wall at " << depth << " m";
    EXPECT_NEAR(field->readings(Vec3d(0.0, 0.0, depth)), 2.0, 0.1) << "wall at " << depth << " m";
    // Facing away from the camera: no data.
    EXPECT_EQ(force(Vec3d(0.0, 0.0, depth + 0.004), -towardCamera), 0.0);
  }
}

TYPED_TEST(DataForceTest, FadesWhereLessThanOneReadingReaches) {
  // One frame: one reading, whose window w(D) is below 1 away from it.
  const auto field = dataTermOf<TypeParam>(wallFrames(3.0, 1));
  const DataForce<TypeParam> force{field.get()};
  const double D = 0.015, window = std::exp(-0.5 * D * D / (kVoxel * kVoxel));
  // The grids interpolate the window between voxels: halfway between two, at
  // 1.5 eps, 14% above w(D).
  EXPECT_NEAR(force(Vec3d(0.0, 0.0, 3.0 + D), Vec3d(0.0, 0.0, -1.0)), D * window, 0.2 * D * window);
  // Beyond the window's reach (3 eps and a voxel), nothing.
  EXPECT_EQ(force(Vec3d(0.0, 0.0, 3.045), Vec3d(0.0, 0.0, -1.0)), 0.0);
}

TYPED_TEST(DataForceTest, ALimitClampsTheForceAndKeepsItsZeros) {
  // The wall at 1 m seen twice: 4 mm behind it the force is 4 mm per unit time.
  const auto field = dataTermOf<TypeParam>(wallFrames(1.0, 2));
  const Vec3d towardCamera(0.0, 0.0, -1.0);
  const DataForce<TypeParam> free{field.get()};
  DataForce<TypeParam> clamped{field.get()};
  clamped.limit = 0.002;
  EXPECT_EQ(clamped(Vec3d(0.0, 0.0, 1.004), towardCamera), 0.002);
  EXPECT_EQ(clamped(Vec3d(0.0, 0.0, 1.004), -towardCamera), 0.0);  // no data stays none
  EXPECT_EQ(clamped(Vec3d(0.0, 0.0, 0.996), towardCamera), -0.002);
  // Below the limit nothing changes: the zero at the wall stays where it was.
  for (int k = -3; k <= 3; ++k) {
    const Vec3d x(0.0, 0.0, 1.0 + 0.0005 * k);
    ASSERT_LT(std::fabs(free(x, towardCamera)), 0.002) << x;
    EXPECT_EQ(clamped(x, towardCamera), free(x, towardCamera)) << x;
  }
}

/// The same speed without atRestIn(): the engine asks it at every point.
struct AskedEverywhere {
  DataSpeed<DataTermGrids> speed;
  float operator()(const ActivePoint& p) const { return speed(p); }
  double curvatureWeight() const { return speed.curvatureWeight(); }
  double stiffness() const { return speed.stiffness(); }
};

/// The field's active points, and those of them in leaves where `speed` is at rest.
struct ActivePointsAtRest {
  std::size_t all = 0, atRest = 0;
};
template <typename Speed>
ActivePointsAtRest activePointsAtRest(const SparseField& field, const Speed& speed) {
  ActivePointsAtRest count;
  const openvdb::FloatGrid& grid = field.grid();
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
    const bool rests = speedAtRestIn(speed, leaf->getNodeBoundingBox(), grid.transform());
    for (auto v = leaf->cbeginValueOn(); v; ++v) {
      if (field.layerOf(v.getCoord()) != 0) continue;
      ++count.all;
      if (rests) ++count.atRest;
    }
  }
  return count;
}

TEST(DataSpeed, WithoutThePriorPointsNoReadingReachesRest) {
  // A wall 0.25 m from a camera cuts the front of a sphere of 0.1 m around
  // (0, 0, 0.3): its readings reach the sphere's front, not its back. Without
  // the prior the back is at rest, and the engine leaves its leaves without
  // asking their points: the same field, value for value, as asking every point.
  const auto field = dataTermOf<DataTermGrids>(wallFrames(0.25, 2));
  DataSpeed<DataTermGrids> speed;
  speed.force.field = field.get();
  const openvdb::FloatGrid::Ptr sphere =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.1f, openvdb::Vec3f(0.0f, 0.0f, 0.3f), kVoxel, 3.0f);
  const openvdb::math::Transform& xform = sphere->transform();
  int atRest = 0, moving = 0;
  for (auto leaf = sphere->tree().cbeginLeaf(); leaf; ++leaf)
    (speedAtRestIn(speed, leaf->getNodeBoundingBox(), xform) ? atRest : moving)++;
  EXPECT_GT(atRest, 20);
  EXPECT_GT(moving, 20);

  SparseField skipping = SparseField::fromLevelSet(*sphere), asking = SparseField::fromLevelSet(*sphere);
  for (int i = 0; i < 4; ++i) {
    const ActivePointsAtRest before = activePointsAtRest(skipping, speed);
    const StepResult skipped = skipping.step(speed);
    const StepResult asked = asking.step(AskedEverywhere{speed});
    // The report counts the points left at rest, and the rms change of the
    // others is the same sum of squared changes over fewer points.
    EXPECT_EQ(skipped.pointsAtRest, before.atRest) << "step " << i;
    EXPECT_EQ(asked.pointsAtRest, 0u);
    EXPECT_EQ(asked.rmsChangeNotAtRest, asked.rmsChange);
    EXPECT_EQ(skipped.rmsChange, asked.rmsChange);
    ASSERT_GT(before.atRest, 0u);
    ASSERT_GT(before.all, before.atRest);
    EXPECT_NEAR(skipped.rmsChangeNotAtRest,
                skipped.rmsChange * std::sqrt(static_cast<double>(before.all) / static_cast<double>(before.all - before.atRest)),
                1e-9 * skipped.rmsChangeNotAtRest);
  }
  const openvdb::FloatTree& a = skipping.grid().tree();
  const openvdb::FloatTree& b = asking.grid().tree();
  ASSERT_EQ(a.activeVoxelCount(), b.activeVoxelCount());
  int changed = 0;
  for (auto it = a.cbeginValueOn(); it; ++it) {
    ASSERT_TRUE(b.isValueOn(it.getCoord())) << it.getCoord();
    ASSERT_EQ(*it, b.getValue(it.getCoord())) << it.getCoord();
    changed += *it != sphere->tree().getValue(it.getCoord());
  }
  EXPECT_GT(changed, 100);  // the data moved the front

  // With the prior every point moves: nothing is at rest.
  speed.beta = 1e-4;
  for (auto leaf = sphere->tree().cbeginLeaf(); leaf; ++leaf)
    EXPECT_FALSE(speedAtRestIn(speed, leaf->getNodeBoundingBox(), xform));
}

}  // namespace
}  // namespace levelfuse

// The data weight on a level set's band, and meshes trimmed by it, on a sphere
// that one scanner saw from one side.

#include "support/TestSupport.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/MeshTrim.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/synth/Synth.h>

#include <openvdb/tools/Interpolation.h>

#include <gtest/gtest.h>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kVoxel = 0.05;

/// The unit sphere seen by one orthographic scanner above it, looking down -z.
RangeMap viewFromAbove() {
  const shapes::Sphere sphere{Vec3d(0.0), 1.0};
  return synth::renderDistanceFunction(sphere, synth::orthographicView(Vec3d(0, 0, -1), Vec3d(0.0), 2.4, 96),
                                       synth::Noise{}, 0.01);
}

double weightAt(const openvdb::FloatGrid& weight, const Vec3d& x) {
  return openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler>(weight).wsSample(x);
}

ForceFieldOptions forceOptions() {
  ForceFieldOptions o;
  o.epsilon = kVoxel;
  o.positionVariance = kVoxel * kVoxel / 120.0;
  return o;
}

/// The weight at the band's voxels near the surface on the seen (z > 0.4) and
/// the unseen (z < -0.4) side of the sphere: the smallest on the seen side and
/// near its top (z > 0.9, where the line of sight is within 26 degrees of the
/// normal), the largest on the other.
struct SideWeights {
  double seenLeast = 1e30, topLeast = 1e30, unseenMost = -1.0;
  std::size_t seen = 0, unseen = 0;
};

SideWeights sideWeights(const openvdb::FloatGrid& weight, const openvdb::FloatGrid& levelSet) {
  SideWeights sides;
  const openvdb::FloatGrid::ConstAccessor weightAt = weight.getConstAccessor();
  for (auto it = levelSet.cbeginValueOn(); it; ++it) {
    const Vec3d p = levelSet.indexToWorld(it.getCoord());
    if (std::fabs(p.length() - 1.0) > 0.5 * kVoxel) continue;  // near the surface
    const auto w = static_cast<double>(weightAt.getValue(it.getCoord()));
    if (p.z() > 0.4) {
      sides.seenLeast = std::min(sides.seenLeast, w);
      if (p.z() > 0.9) sides.topLeast = std::min(sides.topLeast, w);
      ++sides.seen;
    } else if (p.z() < -0.4) {
      sides.unseenMost = std::max(sides.unseenMost, w);
      ++sides.unseen;
    }
  }
  return sides;
}

void expectTheWeightGridOf(const openvdb::FloatGrid& weight, const openvdb::FloatGrid& levelSet) {
  EXPECT_EQ(weight.getName(), kWeightGridName);
  EXPECT_EQ(weight.getGridClass(), openvdb::GRID_UNKNOWN);
  EXPECT_EQ(weight.transform(), levelSet.transform());
  std::size_t facedLeaves = 0;
  EXPECT_TRUE(test::weighsTheBand(weight, levelSet, &facedLeaves));
  EXPECT_GT(facedLeaves, 0u);
  EXPECT_EQ(weight.metaValue<std::string>("levelfuse_surface"), levelSet.getName());
  EXPECT_EQ(weight.metaValue<std::string>("levelfuse_units"), "readings");
}

TEST(SurfaceWeight, IsOneReadingWhereOneScanSawAndZeroBehind) {
  const auto sphere = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  sphere->setName("sphere");
  const RangeMap map = viewFromAbove();
  const ForceField perMap({map}, forceOptions());
  DataTermGrids grids(kVoxel, forceOptions().dataWindow(), forceOptions().positionVariance);
  grids.integrate(map);
  for (const auto& weight : {surfaceWeight(*sphere, perMap), surfaceWeight(*sphere, grids)}) {
    expectTheWeightGridOf(*weight, *sphere);
    const SideWeights sides = sideWeights(*weight, *sphere);
    ASSERT_GT(sides.seen, 100u);
    ASSERT_GT(sides.unseen, 100u);
    // One scan saw the top: one reading, less the window's fall-off within
    // half a voxel of the surface; it saw the sides down to z = 0.4 at up to
    // 66 degrees.
    EXPECT_GT(sides.topLeast, 0.8);
    EXPECT_LT(sides.topLeast, 1.0);
    EXPECT_GT(sides.seenLeast, kObservedWeight);
    EXPECT_EQ(sides.unseenMost, 0.0);
    EXPECT_NEAR(weightAt(*weight, Vec3d(0.0, 0.0, 1.0)), 1.0, 0.02);
  }
}

TEST(SurfaceWeight, HoldsOnlyTheLeavesThatAReadingFaces) {
  // Seen from above, the sphere's lower half is faced by no reading: its
  // leaves are left out of the weight grid, which reads 0 there.
  const auto sphere = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  const ForceField data({viewFromAbove()}, forceOptions());
  const auto weight = surfaceWeight(*sphere, data);
  EXPECT_TRUE(test::weighsTheBand(*weight, *sphere));
  EXPECT_LT(weight->tree().leafCount(), 0.6 * sphere->tree().leafCount());
  EXPECT_GT(weight->tree().leafCount(), 0.3 * sphere->tree().leafCount());
  const openvdb::Coord bottom = openvdb::Coord::round(sphere->worldToIndex(Vec3d(0.0, 0.0, -1.0)));
  ASSERT_NE(sphere->tree().probeConstLeaf(bottom), nullptr);
  EXPECT_EQ(weight->tree().probeConstLeaf(bottom), nullptr);
  EXPECT_EQ(weightAt(*weight, Vec3d(0.0, 0.0, -1.0)), 0.0);
  const openvdb::Coord top = openvdb::Coord::round(sphere->worldToIndex(Vec3d(0.0, 0.0, 1.0)));
  EXPECT_NE(weight->tree().probeConstLeaf(top), nullptr);
}

TEST(SurfaceWeight, FromGridsLeavesOutOnlyTheLeavesNoReadingReaches) {
  // The weight from the grids skips a leaf of the band whose nearest surface
  // points no reading's window reaches (DataTermGrids::mayHaveTermsIn): every
  // voxel holds what the facing terms at its nearest surface point say, one
  // by one, and the leaves left out hold no reading.
  const auto sphere = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  DataTermGrids grids(kVoxel, forceOptions().dataWindow(), forceOptions().positionVariance);
  grids.integrate(viewFromAbove());
  const auto weight = surfaceWeight(*sphere, grids);
  const openvdb::FloatGrid::ConstAccessor phi = sphere->getConstAccessor(), w = weight->getConstAccessor();
  const VoxelNormals normals(*sphere);
  auto sampler = grids.sampler();
  std::size_t weighed = 0, leavesWithoutTerms = 0;
  for (auto leaf = sphere->tree().cbeginLeaf(); leaf; ++leaf) {
    const openvdb::BBoxd around = sphere->transform().indexToWorld(leaf->getNodeBoundingBox().expandBy(3));
    leavesWithoutTerms += !grids.mayHaveTermsIn(around);
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      Vec3d normal;
      if (!normals.at(phi, it.getCoord(), normal)) continue;
      const Vec3d nearest = sphere->indexToWorld(it.getCoord()) - normal * static_cast<double>(*it);
      const auto expected = static_cast<float>(sampler.facingTerms(nearest, normal).readings);
      ASSERT_EQ(w.getValue(it.getCoord()), expected) << it.getCoord();
      weighed += expected > 0.0f;
    }
  }
  EXPECT_GT(weighed, 1000u);
  EXPECT_GT(leavesWithoutTerms, sphere->tree().leafCount() / 4) << "the leaves the short way takes";
}

TEST(SurfaceWeight, IsTheSurfacesWhereTheRaysGraze) {
  // A floor seen at 83 degrees of incidence, its voxels a voxel and more
  // from it along its normal, but many sigmas along the rays: each voxel is
  // weighed at the surface point nearest it, which the readings saw.
  const double voxel = 0.02, floorHeight = -0.5;
  const SphericalProjection grid(-20.0 * M_PI / 180.0, 0.2 * M_PI / 180.0, -12.0 * M_PI / 180.0, 0.2 * M_PI / 180.0);
  const int columns = 201, rows = 41;  // elevations -12 to -4 degrees: the floor 2.4 to 7.2 m away
  std::vector<float> ranges;
  for (int v = 0; v < rows; ++v)
    for (int u = 0; u < columns; ++u) ranges.push_back(static_cast<float>(floorHeight / sphericalDirection(grid, u, v).z()));
  const RangeMap floor = RangeMap::spherical(columns, rows, ranges, grid, openvdb::math::Mat4d::identity(), 0.002, "floor");
  openvdb::FloatGrid::Ptr plane = openvdb::FloatGrid::create(static_cast<float>(3.0 * voxel));
  plane->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  plane->setGridClass(openvdb::GRID_LEVEL_SET);
  for (int x = 150; x <= 250; ++x)
    for (int y = -20; y <= 20; ++y)
      for (int z = -28; z <= -22; ++z) {
        const Vec3d p = plane->indexToWorld(openvdb::Coord(x, y, z));
        plane->tree().setValueOn(openvdb::Coord(x, y, z), static_cast<float>(p.z() - floorHeight));
      }
  const auto weight = surfaceWeight(*plane, ForceField({floor}, forceOptions()));
  const openvdb::FloatGrid::ConstAccessor w = weight->getConstAccessor();
  std::size_t near = 0, observed = 0;
  for (auto it = plane->cbeginValueOn(); it; ++it) {
    const Vec3d p = plane->indexToWorld(it.getCoord());
    if (std::fabs(*it) > 1.5 * voxel || p.x() < 4.0 || p.x() > 4.5 || std::fabs(p.y()) > 0.3) continue;  // 83 degrees
    ++near;
    observed += w.getValue(it.getCoord()) >= kObservedWeight;
  }
  ASSERT_GT(near, 100u);
  EXPECT_EQ(observed, near);
}

TEST(SurfaceWeight, CountsOnlyReadingsThatFaceTheSurface) {
  // A shell thinner than the window: the readings of its outer side reach its
  // inner side, seen from behind, which therefore weighs nothing.
  const auto outer = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  const auto inverted = test::makeSphere((1.0 - kVoxel) / kVoxel, Vec3d(0.0), kVoxel);
  for (auto it = inverted->beginValueOn(); it; ++it) it.setValue(-*it);  // outward normals point to the centre
  const ForceField data({viewFromAbove()}, forceOptions());
  EXPECT_EQ(weightAt(*surfaceWeight(*inverted, data), Vec3d(0.0, 0.0, 1.0 - kVoxel)), 0.0);
  EXPECT_GT(weightAt(*surfaceWeight(*outer, data), Vec3d(0.0, 0.0, 1.0)), 0.9);
}

TEST(SurfaceWeight, RefusesAGridThatIsNotALevelSet) {
  auto fog = openvdb::FloatGrid::create(0.0f);
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  const ForceField data({viewFromAbove()}, forceOptions());
  EXPECT_THROW(surfaceWeight(*fog, data), std::invalid_argument);
}

TEST(SurfaceWeight, StopsWhenItsInterrupterSaysSo) {
  const auto sphere = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  const ForceField data({viewFromAbove()}, forceOptions());
  EXPECT_THROW(surfaceWeight(*sphere, data, [] { return true; }), Interrupted);
}

TEST(SurfaceWeight, TrimmedMeshKeepsTheSeenSideAndDropsTheOther) {
  const auto sphere = test::makeSphere(1.0 / kVoxel, Vec3d(0.0), kVoxel);
  const auto weight = surfaceWeight(*sphere, ForceField({viewFromAbove()}, forceOptions()));
  const TriangleMesh closed = meshFromLevelSet(*sphere);
  const TriangleMesh trimmed = trimMesh(closed, *weight, kObservedWeight);
  std::size_t upperHalf = 0, seenSide = 0;
  for (std::size_t t = 0; t < closed.triangleCount(); ++t) {
    const double z = closed.xyz[3 * closed.triangles[3 * t] + 2];
    upperHalf += z > 0.0;
    seenSide += z > 0.4;
  }
  // The upper half stays down to z = 0.4 at least, but not quite to the
  // equator: the rays that graze it weigh too little (Eq. 38).
  EXPECT_GT(trimmed.triangleCount(), seenSide);
  EXPECT_LT(trimmed.triangleCount(), upperHalf);
  for (std::size_t t = 0; t < trimmed.triangleCount(); ++t) {
    Vec3d centre(0.0);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = trimmed.triangles[3 * t + k];
      centre += Vec3d(trimmed.xyz[3 * v], trimmed.xyz[3 * v + 1], trimmed.xyz[3 * v + 2]) / 3.0;
    }
    ASSERT_GE(weightAt(*weight, centre), kObservedWeight) << "triangle " << t;
    ASSERT_GT(centre.z(), 0.0) << "triangle " << t << " lies on the side no reading saw";
  }
}

TEST(SurfaceWeight, ScenesAreDepthFramesOnly) {
  const shapes::Sphere sphere{Vec3d(0.0), 1.0};
  const RangeMap frame = synth::renderDistanceFunction(
      sphere, synth::pinholeView(Vec3d(0, 0, 4), Vec3d(0.0), 40.0, 32, 24), synth::Noise{}, 0.01);
  EXPECT_TRUE(scansOfAScene({frame, frame}));
  EXPECT_FALSE(scansOfAScene({frame, viewFromAbove()}));
  EXPECT_FALSE(scansOfAScene({}));
}

}  // namespace
}  // namespace levelfuse

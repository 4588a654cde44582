// Building a sparse field from OpenVDB level sets and masks, and writing it back.

#include "support/TestSupport.h"

#include <levelfuse/levelset/Components.h>

#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/ZeroCrossings.h>

#include <openvdb/tools/Diagnostics.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace levelfuse {
namespace {

TEST(SparseFieldConstruction, FromSphereKeepsTheSurfaceAndTheInvariants) {
  const openvdb::Vec3d centre(0.3, -0.2, 0.1);
  const auto sphere = test::makeSphere(20.0, centre);
  const SparseField field = SparseField::fromLevelSet(*sphere);
  const InvariantReport report = checkInvariants(field);
  EXPECT_TRUE(report.ok()) << report.firstViolation;
  EXPECT_EQ(report.inefficientActive, 0u);
  const auto fit = test::fitRadius(field.grid(), centre);
  EXPECT_NEAR(fit.mean, 20.0, 0.02);
  EXPECT_LT(fit.rmsDeviation, 0.02);
  // L0 is the one-voxel slab |u| <= 1/2: about one voxel per voxel^2 of surface.
  const double area = 4.0 * M_PI * 400.0;
  const SparseFieldStats stats = field.stats();
  EXPECT_GT(stats.activeSetVoxels, 0.8 * area);
  EXPECT_LT(stats.activeSetVoxels, 1.3 * area);
  EXPECT_EQ(report.activeSetVoxels, stats.activeSetVoxels);
}

TEST(SparseFieldConstruction, FromAMeshLevelSet) {
  // An octahedron |x| + |y| + |z| = 6 through meshToLevelSet: oblique faces, sharp corners.
  using openvdb::Vec3s;
  const std::vector<Vec3s> points{Vec3s(6, 0, 0), Vec3s(-6, 0, 0), Vec3s(0, 6, 0),
                                  Vec3s(0, -6, 0), Vec3s(0, 0, 6), Vec3s(0, 0, -6)};
  const std::vector<openvdb::Vec3I> triangles{{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const auto transform = openvdb::math::Transform::createLinearTransform(0.25);
  const auto mesh = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, 3.0f);
  SparseField field = SparseField::fromLevelSet(*mesh);
  const InvariantReport report = checkInvariants(field);
  EXPECT_TRUE(report.ok()) << report.firstViolation;
  // The zero crossings lie on the octahedron's faces.
  const double rms = rmsOver(zeroCrossings(field.grid()), [](const openvdb::Vec3d& p) {
    return (std::fabs(p.x()) + std::fabs(p.y()) + std::fabs(p.z()) - 6.0) / std::sqrt(3.0);
  });
  EXPECT_LT(rms, 0.05 * 0.25);
  for (int i = 0; i < 20; ++i) field.step(MeanCurvatureFlow{0.1});
  EXPECT_TRUE(checkInvariants(field).ok());
}

TEST(SparseFieldConstruction, LayersAreCityBlockShells) {
  const SparseField field = SparseField::fromLevelSet(*test::makeSphere(12.0));
  EXPECT_EQ(field.layerOf(openvdb::Coord(12, 0, 0)), 0);
  EXPECT_EQ(field.layerOf(openvdb::Coord(13, 0, 0)), 1);
  EXPECT_EQ(field.layerOf(openvdb::Coord(14, 0, 0)), 2);
  EXPECT_EQ(field.layerOf(openvdb::Coord(15, 0, 0)), 3);   // outside the layers
  EXPECT_EQ(field.layerOf(openvdb::Coord(11, 0, 0)), -1);
  EXPECT_EQ(field.layerOf(openvdb::Coord(10, 0, 0)), -2);
  EXPECT_EQ(field.layerOf(openvdb::Coord(0, 0, 0)), -3);   // deep inside: an inside tile
  EXPECT_EQ(field.layerOf(openvdb::Coord(100, 0, 0)), 3);  // far outside: the background
  EXPECT_FLOAT_EQ(field.grid().tree().getValue(openvdb::Coord(0, 0, 0)), -2.5f);
}

TEST(SparseFieldConstruction, MemoryGrowsWithTheSurfaceNotTheVolume) {
  const SparseFieldStats r100 = SparseField::fromLevelSet(*test::makeSphere(100.0)).stats();
  const SparseFieldStats r200 = SparseField::fromLevelSet(*test::makeSphere(200.0)).stats();
  // Twice the radius: 4x the area, 8x the volume. OpenVDB's top-level nodes
  // around the origin cost a fixed 2 MB, so the ratio stays a little under 4.
  const double ratio = double(r200.memoryBytes) / double(r100.memoryBytes);
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 4.5);
  EXPECT_NEAR(double(r200.bandVoxels) / double(r100.bandVoxels), 4.0, 0.1);
  // Half of a leaf's 512 values lie outside a five-voxel band on average, so
  // the values alone cost about 15 bytes per band voxel; the layer masks and
  // neighbour links add about 5.
  EXPECT_LT(double(r200.memoryBytes) / double(r200.bandVoxels), 24.0);
}

TEST(SparseFieldConstruction, ExportIsAStandardLevelSet) {
  const openvdb::Vec3d centre(1.0, 2.0, 3.0);
  const SparseField field = SparseField::fromLevelSet(*test::makeSphere(15.0, centre, 0.5));
  const openvdb::FloatGrid::Ptr out = field.toLevelSet(3.0, "sphere");
  EXPECT_EQ(out->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(out->getName(), "sphere");
  EXPECT_FLOAT_EQ(out->background(), 1.5f);
  EXPECT_EQ(openvdb::tools::checkLevelSet(*out, 8), "");
  // The band reaches at least 2.5 voxels on each side and the zero set is kept.
  EXPECT_GT(out->tree().activeVoxelCount(), field.stats().bandVoxels);
  const auto fit = test::fitRadius(*out, centre);
  EXPECT_NEAR(fit.mean, 7.5, 0.01);
  const openvdb::FloatGrid::ConstAccessor acc = out->getConstAccessor();
  const openvdb::Coord onAxis = out->transform().worldToIndexNodeCentered(centre + openvdb::Vec3d(7.5 + 1.25, 0, 0));
  EXPECT_TRUE(acc.isValueOn(onAxis));
  EXPECT_NEAR(acc.getValue(onAxis), 1.25, 0.26);
}

TEST(SparseFieldConstruction, AFieldLetGoAsItsLevelSetIsMadeGivesTheSameLevelSet) {
  const SparseField kept = SparseField::fromLevelSet(*test::makeSphere(15.0, openvdb::Vec3d(1.0, 2.0, 3.0), 0.5));
  SparseField letGo = kept;
  const openvdb::FloatGrid::Ptr copied = kept.toLevelSet(3.0, "sphere");
  const openvdb::FloatGrid::Ptr moved = std::move(letGo).toLevelSet(3.0, "sphere");
  std::string why;
  EXPECT_TRUE(test::identical(*copied, *moved, &why)) << why;
  EXPECT_EQ(moved->getName(), "sphere");
  EXPECT_EQ(moved->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(moved->metaValue<openvdb::Int32>("levelfuse_layers"), copied->metaValue<openvdb::Int32>("levelfuse_layers"));
  EXPECT_EQ(openvdb::tools::checkLevelSet(*moved, 8), "");
  EXPECT_THROW(std::move(SparseField(kept)).toLevelSet(0.5), std::invalid_argument);
}

TEST(SparseFieldConstruction, AFieldBuiltFromALevelSetItLetsGoIsTheSame) {
  const openvdb::FloatGrid::Ptr sphere = test::makeSphere(15.0, openvdb::Vec3d(1.0, 2.0, 3.0), 0.5);
  sphere->setName("sphere");
  const SparseField kept = SparseField::fromLevelSet(*sphere);
  openvdb::FloatGrid::Ptr copy = sphere->deepCopy();
  const std::weak_ptr<openvdb::FloatGrid> watched = copy;
  const SparseField built = SparseField::fromLevelSet(std::move(copy));
  EXPECT_FALSE(copy);
  EXPECT_TRUE(watched.expired()) << "the level set is let go";
  std::string why;
  EXPECT_TRUE(test::identical(*kept.toLevelSet(3.0), *built.toLevelSet(3.0), &why)) << why;
  EXPECT_EQ(built.grid().getName(), "sphere");
  EXPECT_EQ(built.stats().bandVoxels, kept.stats().bandVoxels);
  EXPECT_THROW(SparseField::fromLevelSet(openvdb::FloatGrid::Ptr()), std::invalid_argument);
}

TEST(SparseFieldConstruction, FromMaskPutsTheSurfaceBetweenVoxels) {
  openvdb::MaskGrid::Ptr mask = openvdb::MaskGrid::create();
  mask->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
  // A 10x10x10 cube of inside voxels 0..9, with a 64^3 tile inside a bigger block
  // to exercise tiles: a second cube made of one active tile.
  mask->tree().fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(9)), true, true);
  mask->tree().addTile(1, openvdb::Coord(64, 0, 0), true, true);  // voxels 64..71 in x, 0..7 in y, z
  const SparseField field = SparseField::fromMask(*mask);
  const InvariantReport report = checkInvariants(field);
  EXPECT_TRUE(report.ok()) << report.firstViolation;
  EXPECT_FLOAT_EQ(field.grid().tree().getValue(openvdb::Coord(9, 5, 5)), -0.5f);
  EXPECT_FLOAT_EQ(field.grid().tree().getValue(openvdb::Coord(10, 5, 5)), 0.5f);
  EXPECT_EQ(field.layerOf(openvdb::Coord(5, 5, 5)), -3);
  EXPECT_EQ(field.layerOf(openvdb::Coord(71, 3, 3)), 0);
  EXPECT_EQ(field.layerOf(openvdb::Coord(72, 3, 3)), 0);
  EXPECT_EQ(field.layerOf(openvdb::Coord(70, 3, 3)), -1);
  EXPECT_EQ(insideComponents(field.grid()), 2);
}

TEST(SparseFieldConstruction, RejectsWhatIsNotALevelSet) {
  openvdb::FloatGrid::Ptr fog = openvdb::FloatGrid::create(0.0f);
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->tree().setValue(openvdb::Coord(0), 1.0f);
  try {
    SparseField::fromLevelSet(*fog);
    FAIL() << "a fog volume was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("grid 'density' is a fog volume"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fogToSdf"), std::string::npos) << e.what();
  }

  openvdb::FloatGrid::Ptr stretched = test::makeSphere(5.0);
  openvdb::math::Mat4d scale = openvdb::math::Mat4d::identity();
  scale.preScale(openvdb::Vec3d(1.0, 2.0, 1.0));
  stretched->setTransform(openvdb::math::Transform::createLinearTransform(scale));
  EXPECT_THROW(SparseField::fromLevelSet(*stretched), std::invalid_argument);

  openvdb::FloatGrid::Ptr bad = test::makeSphere(5.0);
  bad->tree().setValue(openvdb::Coord(5, 0, 0), std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(SparseField::fromLevelSet(*bad), std::invalid_argument);

  openvdb::FloatGrid::Ptr empty = openvdb::FloatGrid::create(3.0f);
  empty->setGridClass(openvdb::GRID_LEVEL_SET);
  EXPECT_THROW(SparseField::fromLevelSet(*empty), std::invalid_argument);

  SparseFieldOptions options;
  options.maxStepChange = 0.5;
  EXPECT_THROW(SparseField::fromLevelSet(*test::makeSphere(5.0), options), std::invalid_argument);
  options = SparseFieldOptions{};
  options.layers = 1;
  EXPECT_THROW(SparseField::fromLevelSet(*test::makeSphere(5.0), options), std::invalid_argument);
}

TEST(SparseFieldConstruction, CopiesAreIndependent) {
  SparseField a = SparseField::fromLevelSet(*test::makeSphere(8.0));
  SparseField b = a;
  for (int i = 0; i < 10; ++i) b.step(ConstantSpeed{ConstantForce{1.0}});
  EXPECT_NEAR(test::fitRadius(a.grid(), openvdb::Vec3d(0.0)).mean, 8.0, 0.05);
  EXPECT_GT(test::fitRadius(b.grid(), openvdb::Vec3d(0.0)).mean, 10.0);
  EXPECT_TRUE(checkInvariants(a).ok());
  EXPECT_TRUE(checkInvariants(b).ok());
}

TEST(SparseFieldConstruction, WorksWithFinerLayersToo) {
  SparseFieldOptions options;
  options.layers = 3;
  SparseField field = SparseField::fromLevelSet(*test::makeSphere(10.0), options);
  EXPECT_EQ(field.layerOf(openvdb::Coord(13, 0, 0)), 3);
  for (int i = 0; i < 20; ++i) field.step(MeanCurvatureFlow{1.0});
  const InvariantReport report = checkInvariants(field);
  EXPECT_TRUE(report.ok()) << report.firstViolation;
}

}  // namespace
}  // namespace levelfuse

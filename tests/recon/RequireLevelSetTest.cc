// Every entry point that takes a level set refuses what is not one, the same
// way: naming itself and the grid, with a hint.

#include "support/TestSupport.h"

#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/DataFit.h>

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {
namespace {

/// The sphere test::makeSphere makes, named "ball", spoilt by `spoil`.
openvdb::FloatGrid::Ptr spoiltSphere(const std::function<void(openvdb::FloatGrid&)>& spoil) {
  openvdb::FloatGrid::Ptr grid = test::makeSphere(5.0);
  grid->setName("ball");
  spoil(*grid);
  return grid;
}

/// The ways a grid can fail to be a level set, each with words its message must hold.
std::vector<std::pair<openvdb::FloatGrid::Ptr, std::string>> notLevelSets() {
  return {
      {spoiltSphere([](openvdb::FloatGrid& g) { g.setGridClass(openvdb::GRID_FOG_VOLUME); }), "fogToSdf"},
      {spoiltSphere([](openvdb::FloatGrid& g) { g.setGridClass(openvdb::GRID_UNKNOWN); }),
       "set its class to openvdb::GRID_LEVEL_SET"},
      {spoiltSphere([](openvdb::FloatGrid& g) {
         openvdb::math::Mat4d scale = openvdb::math::Mat4d::identity();
         scale.preScale(openvdb::Vec3d(1.0, 2.0, 1.0));
         g.setTransform(openvdb::math::Transform::createLinearTransform(scale));
       }),
       "non-uniform voxels"},
      {spoiltSphere([](openvdb::FloatGrid& g) {
         g.setTransform(openvdb::math::Transform::createFrustumTransform(
             openvdb::BBoxd(openvdb::Vec3d(-10.0), openvdb::Vec3d(10.0)), 0.5, 10.0, 1.0));
       }),
       "frustum"},
      {spoiltSphere([](openvdb::FloatGrid& g) { g.tree().root().setBackground(-1.0f, false); }),
       "changeLevelSetBackground"},
      {spoiltSphere([](openvdb::FloatGrid& g) {
         g.tree().root().setBackground(std::numeric_limits<float>::infinity(), false);
       }),
       "background"},
      // FuzzVdb: a file's NaN reached OpenVDB's mesher, which threw from inside its TBB tasks.
      {spoiltSphere([](openvdb::FloatGrid& g) {
         g.tree().setValueOff(openvdb::Coord(5, 0, 0), std::numeric_limits<float>::quiet_NaN());
       }),
       "holds a value that is not finite at voxel [5, 0, 0]; a level set holds finite distances "
       "(openvdb::tools::checkLevelSet"},
      {spoiltSphere([](openvdb::FloatGrid& g) {
         g.tree().addTile(1, openvdb::Coord(128, 0, 0), -std::numeric_limits<float>::infinity(), false);
       }),
       "not finite at voxel [128, 0, 0]"},
  };
}

TEST(RequireLevelSet, ALevelSetPasses) {
  EXPECT_EQ(levelSetProblem(*test::makeSphere(5.0)), "");
  EXPECT_NO_THROW(requireLevelSet(*test::makeSphere(5.0), "test"));
}

TEST(RequireLevelSet, EveryEntryPointRefusesWhatIsNotALevelSetTheSameWay) {
  const std::vector<std::pair<std::string, std::function<void(const openvdb::FloatGrid&)>>> entryPoints = {
      {"SparseField::fromLevelSet", [](const openvdb::FloatGrid& g) { SparseField::fromLevelSet(g); }},
      {"refineLevelSet", [](const openvdb::FloatGrid& g) { refineLevelSet(g); }},
      {"meshFromLevelSet", [](const openvdb::FloatGrid& g) { meshFromLevelSet(g); }},
      {"DenseField::fromLevelSet",
       [](const openvdb::FloatGrid& g) {
         DenseField::fromLevelSet(g, openvdb::CoordBBox(openvdb::Coord(-8), openvdb::Coord(8)));
       }},
      {"zeroCrossings", [](const openvdb::FloatGrid& g) { zeroCrossings(g); }},
      {"insideComponents", [](const openvdb::FloatGrid& g) { insideComponents(g); }},
      {"measureDataFit",
       [](const openvdb::FloatGrid& g) { measureDataFit(g, std::vector<openvdb::Vec3d>{openvdb::Vec3d(0.0)}); }},
      {"renderPreview", [](const openvdb::FloatGrid& g) { io::renderPreview(g); }},
      {"writePreviewPng",
       [](const openvdb::FloatGrid& g) { io::writePreviewPng(g, ::testing::TempDir() + "levelfuse-never.png", {}); }},
  };
  for (const auto& [grid, hint] : notLevelSets())
    for (const auto& [who, call] : entryPoints) {
      try {
        call(*grid);
        ADD_FAILURE() << who << " accepted a grid that should need " << hint;
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(who + ": the grid 'ball' ", 0), 0u) << what;
        EXPECT_NE(what.find(hint), std::string::npos) << what;
      }
    }
}

}  // namespace
}  // namespace levelfuse

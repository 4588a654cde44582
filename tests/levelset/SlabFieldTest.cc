// A sparse field cut into slabs and stepped slab by slab, exchanging ghosts,
// is bit-identical to the whole field stepped at once: the slabs run in one
// process here, as MPI ranks run them (mpi/).

#include "support/TestSupport.h"
#include "support/ThreadTeam.h"

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SlabFieldStep.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>

#include <gtest/gtest.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

/// Every slab's ghosts replaced by its neighbours' leaves.
void refreshGhosts(std::vector<SlabField>& slabs) {
  std::vector<PackedLeaves> toLower(slabs.size()), toHigher(slabs.size());
  for (std::size_t i = 0; i < slabs.size(); ++i) {
    toLower[i] = slabs[i].ghostsFor(SlabSide::kLower);
    toHigher[i] = slabs[i].ghostsFor(SlabSide::kHigher);
  }
  for (std::size_t i = 0; i < slabs.size(); ++i) {
    if (i > 0) slabs[i].acceptGhosts(SlabSide::kLower, toHigher[i - 1]);
    if (i + 1 < slabs.size()) slabs[i].acceptGhosts(SlabSide::kHigher, toLower[i + 1]);
  }
}

/// One step of the whole field, slab by slab, as the ranks of an MPI run take it.
template <typename Speed>
StepResult stepSlabs(std::vector<SlabField>& slabs, const Speed& speed) {
  refreshGhosts(slabs);
  double maxSpeed = 0.0;
  for (SlabField& slab : slabs) maxSpeed = std::max(maxSpeed, slab.computeRates(speed));
  const double dt = slabs.front().timeStep(maxSpeed, speed.curvatureWeight(), speedStiffness(speed),
                                           std::numeric_limits<double>::infinity());
  StepTally total;
  for (SlabField& slab : slabs) total += slab.applyRates(dt, maxSpeed);
  return total.result(slabs.front().voxelSize());
}

std::vector<SlabField> cut(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Int32>& cuts) {
  std::vector<SlabField> slabs;
  SlabBounds bounds;
  for (std::size_t i = 0; i <= cuts.size(); ++i) {
    bounds.end = i < cuts.size() ? cuts[i] : SlabBounds::kUnbounded;
    slabs.push_back(SlabField::fromLevelSet(levelSet, bounds));
    bounds.begin = bounds.end;
  }
  return slabs;
}

SparseField assembled(const std::vector<SlabField>& slabs, const openvdb::FloatGrid& levelSet) {
  std::vector<PackedLeaves> pieces;
  for (const SlabField& slab : slabs) pieces.push_back(slab.ownedLeaves());
  return SlabField::assemble(pieces, levelSet);
}

/// Layers of every band voxel agree, and so do the values and tiles.
void expectSameField(const SparseField& whole, const SparseField& parts, const std::string& when) {
  std::string why;
  EXPECT_TRUE(test::identical(whole.grid(), parts.grid(), &why)) << when << ": " << why;
  EXPECT_TRUE(whole.grid().tree().hasSameTopology(parts.grid().tree())) << when;
  EXPECT_EQ(test::voxelsInOtherLayers(whole, parts), 0u) << when << ": band voxels in different layers";
}

void expectSameStep(const StepResult& a, const StepResult& b, int step) {
  EXPECT_EQ(a.dt, b.dt) << "step " << step;
  EXPECT_EQ(a.maxSpeed, b.maxSpeed) << "step " << step;
  EXPECT_EQ(a.maxChange, b.maxChange) << "step " << step;
  EXPECT_EQ(a.rmsChange, b.rmsChange) << "step " << step;
  EXPECT_EQ(a.activeSetVoxels, b.activeSetVoxels) << "step " << step;
  EXPECT_EQ(a.movedOut, b.movedOut) << "step " << step;
  EXPECT_EQ(a.movedIn, b.movedIn) << "step " << step;
  EXPECT_EQ(a.conflicts, b.conflicts) << "step " << step;
}

/// Steps the whole field and the slabs `steps` times under `speed`, checking
/// every step's report and, every `checkEvery` steps and at the end, the field.
template <typename Speed>
SparseField expectSlabsFollowTheWhole(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Int32>& cuts,
                                      const Speed& speed, int steps, int checkEvery = 10) {
  SparseField whole = SparseField::fromLevelSet(levelSet);
  std::vector<SlabField> slabs = cut(levelSet, cuts);
  expectSameField(whole, assembled(slabs, levelSet), "as built");
  for (int s = 1; s <= steps; ++s) {
    const StepResult a = whole.step(speed);
    const StepResult b = stepSlabs(slabs, speed);
    expectSameStep(a, b, s);
    if (s % checkEvery == 0 || s == steps) expectSameField(whole, assembled(slabs, levelSet), "step " + std::to_string(s));
    if (::testing::Test::HasFailure()) return whole;
  }
  std::string why;
  EXPECT_TRUE(test::identical(*whole.toLevelSet(3.0), *assembled(slabs, levelSet).toLevelSet(3.0), &why)) << why;
  return whole;
}

/// The smallest and largest x of the field's leaves.
std::pair<int, int> leafExtentX(const SparseField& field) {
  const openvdb::CoordBBox box = field.grid().evalActiveVoxelBoundingBox();
  return {box.min().x(), box.max().x()};
}

openvdb::FloatGrid::Ptr sample(const std::function<double(const Vec3d&)>& f, const openvdb::BBoxd& box) {
  return levelSetFromFunction(f, box, 1.0);
}

/// A force that varies over space and with the normal, sampled at subcell positions.
ExternalForceSpeed varyingForce() {
  return ExternalForceSpeed{[](const Vec3d& x, const Vec3d& n) {
                              return 0.5 * std::sin(0.4 * x.x()) + 0.3 * std::cos(0.3 * x.y()) + 0.1 * n.x();
                            },
                            0.5, ForceSampling::kSubcell};
}

TEST(SlabField, ACurvatureFlowCutInTwoIsTheWholeFlow) {
  // The cut at x = 0 passes through the sphere's middle.
  const auto sphere = sample(shapes::Sphere{Vec3d(0.3, -0.2, 0.1), 14.0}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  expectSlabsFollowTheWhole(*sphere, {0}, MeanCurvatureFlow{1.0}, 40);
}

TEST(SlabField, FourSlabsOneLeafWideFollowTheWhole) {
  // Slabs of one and two columns of leaves: ghosts come from both sides of a
  // one-column slab, and the outer slabs hold the sphere's caps.
  const auto sphere = sample(shapes::Sphere{Vec3d(0.3, -0.2, 0.1), 14.0}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  expectSlabsFollowTheWhole(*sphere, {-8, 0, 16}, MeanCurvatureFlow{1.0}, 30);
}

TEST(SlabField, AGrowingSurfaceCrossesIntoTheNextSlabs) {
  // The sphere starts inside the middle slab [-8, 8) and grows through both
  // of its faces into slabs that hold no leaf at first.
  const auto sphere = sample(shapes::Sphere{Vec3d(0.4, 0.1, -0.3), 5.0}, openvdb::BBoxd(Vec3d(-9), Vec3d(9)));
  ASSERT_GT(leafExtentX(SparseField::fromLevelSet(*sphere)).first, -16);
  const SparseField grown = expectSlabsFollowTheWhole(*sphere, {-8, 8}, ConstantSpeed{ConstantForce{1.0}, 0.2}, 60);
  EXPECT_LT(leafExtentX(grown).first, -16);
  EXPECT_GE(leafExtentX(grown).second, 16);
}

TEST(SlabField, SpheresMergingAcrossACutFollowTheWhole) {
  // Two spheres, one on each side of the cut at x = 0, grow into one.
  const auto twoSpheres = sample(
      [](const Vec3d& p) {
        return std::min(shapes::Sphere{Vec3d(-7.6, 0.2, 0.1), 6.0}(p), shapes::Sphere{Vec3d(7.4, -0.1, 0.3), 6.0}(p));
      },
      openvdb::BBoxd(Vec3d(-16, -9, -9), Vec3d(16, 9, 9)));
  ASSERT_GT(twoSpheres->tree().getValue(openvdb::Coord(0)), 0.0f);
  const SparseField merged = expectSlabsFollowTheWhole(*twoSpheres, {0}, ConstantSpeed{ConstantForce{1.0}, 0.1}, 30);
  EXPECT_LT(merged.grid().tree().getValue(openvdb::Coord(0)), 0.0f) << "the spheres have not merged";
}

TEST(SlabField, AFaceAlongTheCutAndAThinTorusFollowTheWhole) {
  // A box whose face lies along the cut's voxel plane x = 8 (between x = 7
  // and x = 8), shrinking under curvature; a torus whose thin tube the cuts
  // cross, under a force that varies in space.
  const auto box = sample(shapes::Box{Vec3d(-2.5, 0.2, -0.1), Vec3d(10.0, 7.2, 6.9)}, openvdb::BBoxd(Vec3d(-16), Vec3d(11)));
  expectSlabsFollowTheWhole(*box, {8}, MeanCurvatureFlow{1.0}, 30);
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 2.6}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  const ExternalForceSpeed force{[](const Vec3d& x, const Vec3d& n) {
                                   return 0.6 * std::sin(0.3 * x.x()) + 0.4 * std::cos(0.2 * x.y() + 0.1 * x.z()) +
                                          0.1 * n.z();
                                 },
                                 0.8, ForceSampling::kSubcell};
  expectSlabsFollowTheWhole(*torus, {-8, 8}, force, 40);
}

TEST(SlabField, SlabsRefinedOneByOneAreTheRefinedWhole) {
  // Coarse to fine as the reconstruction goes: each slab's level set is
  // refined to half the voxel size on its own and becomes the slab of the
  // finer grid twice as many voxels wide.
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 3.1}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  const ExternalForceSpeed force = varyingForce();
  SparseField whole = SparseField::fromLevelSet(*torus);
  std::vector<SlabField> slabs = cut(*torus, {-8, 0, 16});
  for (int s = 0; s < 15; ++s) {
    whole.step(force);
    stepSlabs(slabs, force);
  }
  const openvdb::FloatGrid::Ptr fineWhole = refineLevelSet(*whole.toLevelSet(3.0));
  SparseField wholeFine = SparseField::fromLevelSet(*fineWhole);
  refreshGhosts(slabs);
  std::vector<SlabField> fine;
  for (const SlabField& slab : slabs) {
    fine.push_back(SlabField::fromLevelSet(*refineLevelSet(*slab.toLevelSet(3.0)), onFinerGrid(slab.bounds())));
  }
  expectSameField(wholeFine, assembled(fine, *fineWhole), "refined");
  for (int s = 1; s <= 15; ++s) expectSameStep(wholeFine.step(force), stepSlabs(fine, force), s);
  expectSameField(wholeFine, assembled(fine, *fineWhole), "refined and stepped");
}

TEST(SlabField, SlabsCopiedFromAFieldRefineAsTheWhole) {
  // Slabs copied from a field (fromField) hold its leaves and no tiles: the
  // inside of a shape is a tile of the outside's value in them. Refining
  // must not take a side from tiles. Shapes of several sizes, so that the
  // band grows into cells without leaves somewhere.
  const MeanCurvatureFlow flow{1.0};
  for (const double radius : {9.3, 13.7, 17.2, 21.6}) {
    const auto ball = sample(shapes::Sphere{Vec3d(0.41, -0.27, 0.13), radius},
                             openvdb::BBoxd(Vec3d(-radius - 4), Vec3d(radius + 4)));
    SparseField whole = SparseField::fromLevelSet(*ball);
    for (int s = 0; s < 3; ++s) whole.step(flow);
    std::vector<SlabField> slabs;
    SlabBounds bounds;
    for (const openvdb::Int32 end : {-8, 8, SlabBounds::kUnbounded}) {
      bounds.end = end;
      slabs.push_back(SlabField::fromField(whole, bounds));
      bounds.begin = end;
    }
    expectSameField(whole, assembled(slabs, *ball), "copied");
    std::vector<SlabField> fine;
    for (const SlabField& slab : slabs) {
      fine.push_back(SlabField::fromLevelSet(*refineLevelSet(*slab.toLevelSet(3.0)), onFinerGrid(slab.bounds())));
    }
    const openvdb::FloatGrid::Ptr fineWhole = refineLevelSet(*whole.toLevelSet(3.0));
    expectSameField(SparseField::fromLevelSet(*fineWhole), assembled(fine, *fineWhole),
                    "refined, radius " + std::to_string(radius));
  }
}

TEST(SlabField, ATeamRefinesItsSlabsAndCutsTheFinerGridAfresh) {
  // Three ranks whose coarse slabs share the torus out unevenly (the first
  // two hold a column of leaf nodes each, the last the other two):
  // refineAcrossTeam cuts the finer grid where its leaf nodes share out
  // evenly, each rank hands its refined leaves to their new owners, and the
  // slabs follow the whole refined field.
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 3.1}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  const ExternalForceSpeed force = varyingForce();
  SparseField whole = SparseField::fromLevelSet(*torus);
  for (int s = 0; s < 8; ++s) whole.step(force);
  const openvdb::FloatGrid::Ptr fineLevelSet = refineLevelSet(*whole.toLevelSet(3.0));
  SparseField wholeFine = SparseField::fromLevelSet(*fineLevelSet);
  std::vector<StepResult> wholeSteps;
  for (int s = 0; s < 8; ++s) wholeSteps.push_back(wholeFine.step(force));

  const std::vector<openvdb::Int32> coarseCuts = {-8, 0};
  const std::vector<openvdb::FloatGrid::Ptr> torusCopies = {torus->deepCopy(), torus->deepCopy(), torus->deepCopy()};
  std::vector<std::size_t> fineLeaves(3);
  std::vector<std::vector<StepResult>> teamSteps(3);
  std::optional<SparseField> assembledFine;
  test::runOnThreadTeam(3, [&](const SlabTeam& team) {
    const std::size_t r = static_cast<std::size_t>(team.rank());
    SlabBounds bounds;
    if (r > 0) bounds.begin = coarseCuts[r - 1];
    if (r < 2) bounds.end = coarseCuts[r];
    // Each rank reads its own copy, as a process would: OpenVDB registers
    // the accessors of a tree in the tree.
    SlabField slab = SlabField::fromLevelSet(*torusCopies[r], bounds);
    for (int s = 0; s < 8; ++s) stepSlab(slab, force, team);
    slab = refineAcrossTeam(std::move(slab), team, {});
    for (int s = 0; s < 8; ++s) teamSteps[r].push_back(stepSlab(slab, force, team));
    fineLeaves[r] = slab.stats().leafNodes;
    std::vector<PackedLeaves> pieces = team.gather(slab.ownedLeaves(), 0);
    if (r == 0) assembledFine = SlabField::assemble(std::move(pieces), *fineLevelSet);
  });
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t s = 0; s < wholeSteps.size(); ++s) expectSameStep(wholeSteps[s], teamSteps[r][s], static_cast<int>(s));
  ASSERT_TRUE(assembledFine);
  expectSameField(wholeFine, *assembledFine, "refined across the team and stepped");
  const std::size_t leaves = fineLeaves[0] + fineLeaves[1] + fineLeaves[2];
  EXPECT_EQ(leaves, wholeFine.stats().leafNodes);
  for (std::size_t r = 0; r < 3; ++r) EXPECT_LT(fineLeaves[r], leaves / 2) << "rank " << r << " of an even share";
  for (std::size_t r = 0; r < 3; ++r) EXPECT_GT(fineLeaves[r], leaves / 5) << "rank " << r << " of an even share";
}

TEST(SlabField, ASlabsLevelSetKnowsTheSideOfTheCellsBesideItsLeaves) {
  // A slab's own flood fill cannot see the band beyond its ghosts; the side
  // of every cell beside its leaves (where refinement samples) is the whole
  // field's. A large sphere: many of the slabs' internal nodes are cut.
  const auto sphere = sample(shapes::Sphere{Vec3d(3.3, -70.2, 5.1), 57.0}, openvdb::BBoxd(Vec3d(-60, -130, -60), Vec3d(62, -10, 62)));
  const SparseField whole = SparseField::fromLevelSet(*sphere);
  const openvdb::FloatGrid::Ptr wholeSet = whole.toLevelSet(3.0);
  std::vector<SlabField> slabs = cut(*sphere, {-40, 0, 24});
  refreshGhosts(slabs);
  std::size_t cells = 0, wrong = 0;
  for (const SlabField& slab : slabs) {
    const openvdb::FloatGrid::Ptr piece = slab.toLevelSet(3.0);
    const openvdb::Int32 lo = slab.bounds().hasLower() ? slab.bounds().begin - 8 : -1000;
    const openvdb::Int32 hi = slab.bounds().hasHigher() ? slab.bounds().end + 8 : 1000;
    for (auto leaf = piece->tree().cbeginLeaf(); leaf; ++leaf)
      for (int d = 0; d < 27; ++d) {
        const openvdb::Coord cell = leaf->origin().offsetBy((d / 9 - 1) * 8, (d / 3 % 3 - 1) * 8, (d % 3 - 1) * 8);
        if (cell.x() < lo || cell.x() >= hi || piece->tree().probeConstLeaf(cell)) continue;
        ++cells;
        const bool bad = (piece->tree().getValue(cell) < 0.0f) != (wholeSet->tree().getValue(cell) < 0.0f);
        wrong += bad;
      }
  }
  EXPECT_GT(cells, 1000u);
  EXPECT_EQ(wrong, 0u) << "of " << cells << " cells beside the slabs' leaves";
}

TEST(SlabField, ASlabLetGoAsItsLevelSetIsMadeGivesTheSameLevelSet) {
  const auto sphere = sample(shapes::Sphere{Vec3d(3.3, -70.2, 5.1), 57.0}, openvdb::BBoxd(Vec3d(-60, -130, -60), Vec3d(62, -10, 62)));
  std::vector<SlabField> slabs = cut(*sphere, {-40, 0, 24});
  refreshGhosts(slabs);
  for (SlabField& slab : slabs) {
    const openvdb::FloatGrid::Ptr copied = slab.toLevelSet(3.0, "s");
    const openvdb::FloatGrid::Ptr moved = std::move(slab).toLevelSet(3.0, "s");
    std::string why;
    EXPECT_TRUE(test::identical(*copied, *moved, &why)) << why;
    EXPECT_EQ(moved->getName(), "s");
  }
}

TEST(SlabField, ASlabBuiltFromALevelSetItLetsGoIsTheSame) {
  const auto sphere = sample(shapes::Sphere{Vec3d(3.3, -70.2, 5.1), 57.0}, openvdb::BBoxd(Vec3d(-60, -130, -60), Vec3d(62, -10, 62)));
  for (const SlabBounds& bounds : {SlabBounds{-40, 0}, SlabBounds{SlabBounds().begin, -40}, SlabBounds{24, SlabBounds().end}}) {
    const SlabField kept = SlabField::fromLevelSet(*sphere, bounds);
    openvdb::FloatGrid::Ptr copy = sphere->deepCopy();
    const std::weak_ptr<openvdb::FloatGrid> watched = copy;
    const SlabField built = SlabField::fromLevelSet(std::move(copy), bounds);
    EXPECT_TRUE(watched.expired()) << "the level set is let go";
    std::string why;
    EXPECT_TRUE(test::identical(*kept.toLevelSet(3.0), *built.toLevelSet(3.0), &why)) << why;
    EXPECT_EQ(built.ownedLeaves(), kept.ownedLeaves());
  }
}

TEST(SlabField, TheSlabsLevelSetPiecesAssembleIntoTheWholesLevelSet) {
  // The output of a shared evolution: each slab packs its own leaves of its
  // level set, one process puts them together. Shapes whose insides span
  // several slabs, cut through internal nodes and along their faces (x = 0,
  // 128), after steps that moved the surface across the cuts.
  const ExternalForceSpeed force{[](const Vec3d& x, const Vec3d&) { return 0.6 + 0.4 * std::sin(0.3 * x.y()); }, 0.3,
                                 ForceSampling::kSubcell};
  const auto shapes = {sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 3.1}, openvdb::BBoxd(Vec3d(-18), Vec3d(18))),
                       sample(shapes::Sphere{Vec3d(60.3, -20.2, 5.1), 71.0}, openvdb::BBoxd(Vec3d(-15, -95, -70), Vec3d(135, 55, 80)))};
  for (const auto& shape : shapes) {
    SparseField whole = SparseField::fromLevelSet(*shape);
    std::vector<SlabField> slabs = cut(*shape, {-8, 0, 16, 128});
    for (int s = 0; s < 6; ++s) {
      whole.step(force);
      stepSlabs(slabs, force);
    }
    refreshGhosts(slabs);
    std::vector<PackedLeaves> pieces;
    for (const SlabField& slab : slabs) pieces.push_back(packLevelSetLeaves(*slab.toLevelSet(3.0, "s"), slab.bounds()));
    // The pieces in reverse order: the order must not matter.
    std::reverse(pieces.begin(), pieces.end());
    const openvdb::FloatGrid::Ptr wholeSet = whole.toLevelSet(3.0, "s");
    const openvdb::FloatGrid::Ptr assembledSet = assembleLevelSet(pieces, *slabs.front().toLevelSet(3.0, "s"));
    std::string why;
    EXPECT_TRUE(test::identical(*wholeSet, *assembledSet, &why)) << why;
    EXPECT_TRUE(test::sameTreeBytes(*wholeSet, *assembledSet)) << "the trees' tiles or nodes differ";
    EXPECT_EQ(assembledSet->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_EQ(assembledSet->getName(), "s");
    EXPECT_EQ(assembledSet->background(), wholeSet->background());
    EXPECT_GT(wholeSet->tree().leafCount(), 50u);
  }
}

TEST(SlabField, ParcelsOfASlabAreWholeColumnsOfAtMostSoManyLeaves) {
  const auto sphere = sample(shapes::Sphere{Vec3d(3.1, -2.0, 0.7), 30.0}, openvdb::BBoxd(Vec3d(-35), Vec3d(40)));
  const openvdb::FloatTree& tree = sphere->tree();
  const SlabBounds slab{-16, 24};
  const auto columns = leafColumns(tree, slab);
  std::size_t inSlab = 0, widest = 0;
  for (const auto& column : columns) {
    inSlab += column.second;
    widest = std::max(widest, column.second);
  }
  ASSERT_GT(columns.size(), 3u);
  for (const std::size_t most : {std::size_t{1}, widest - 1, widest, widest + 7, 2 * widest + 1, inSlab}) {
    const std::vector<SlabBounds> parcels = parcelsOf(tree, slab, most);
    ASSERT_FALSE(parcels.empty());
    EXPECT_EQ(parcels.front().begin, slab.begin);
    EXPECT_EQ(parcels.back().end, slab.end);
    std::size_t counted = 0;
    for (std::size_t k = 0; k < parcels.size(); ++k) {
      if (k > 0) {
        EXPECT_EQ(parcels[k].begin, parcels[k - 1].end) << "parcels " << k - 1 << " and " << k << " meet";
      }
      const auto held = leafColumns(tree, parcels[k]);
      std::size_t leaves = 0;
      for (const auto& column : held) leaves += column.second;
      EXPECT_GT(leaves, 0u) << "parcel " << k << " of at most " << most;
      EXPECT_TRUE(leaves <= most || held.size() == 1) << "parcel " << k << " holds " << leaves << " of at most " << most;
      // Full: the next column would not have fit.
      if (k + 1 < parcels.size()) {
        EXPECT_GT(leaves + leafColumns(tree, parcels[k + 1]).front().second, most);
      }
      counted += leaves;
    }
    EXPECT_EQ(counted, inSlab) << "every leaf of the slab in one parcel, at most " << most;
    if (most >= inSlab) {
      EXPECT_EQ(parcels.size(), 1u);
    }
  }
  const std::vector<SlabBounds> none = parcelsOf(tree, SlabBounds{400, 480}, 5);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none.front().begin, 400);
  EXPECT_EQ(none.front().end, 480);
  EXPECT_THROW(parcelsOf(tree, slab, 0), std::invalid_argument);
}

TEST(SlabField, ATeamGathersItsLevelSetParcelByParcel) {
  // Three ranks' slabs of a torus gathered at the first in parcels of at
  // most 7 leaf nodes (a column each: two rounds or more), and of the default
  // size (one round): the level set put together is the whole's.
  const auto torus = sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 3.1}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)));
  const std::vector<SlabBounds> slabs{{-SlabBounds::kUnbounded, -8}, {-8, 8}, {8, SlabBounds::kUnbounded}};
  for (const std::size_t parcel : {std::size_t{7}, kLeavesPerParcel}) {
    std::vector<openvdb::FloatGrid::Ptr> pieces;
    for (const SlabBounds& slab : slabs) {
      pieces.push_back(torus->copyWithNewTree());
      addLevelSetLeaves(*pieces.back(), packLevelSetLeaves(*torus, levelSetReach(slab)));  // its neighbours' leaves beside its own
    }
    const openvdb::FloatGrid::Ptr whole = torus->copyWithNewTree();
    test::runOnThreadTeam(3, [&](const SlabTeam& team) {
      const std::size_t r = static_cast<std::size_t>(team.rank());
      gatherLevelSetLeaves(pieces[r], slabs[r], *whole, team, parcel);
      EXPECT_FALSE(pieces[r]) << "rank " << r << " let its piece go";
    });
    closeAssembledLevelSet(*whole);
    std::string why;
    EXPECT_TRUE(test::identical(*torus, *whole, &why)) << "parcels of " << parcel << ": " << why;
    EXPECT_TRUE(test::sameTreeBytes(*torus, *whole)) << "parcels of " << parcel << ": the trees' tiles or nodes differ";
  }
  for (const SlabBounds& slab : slabs) EXPECT_GE(parcelsOf(torus->tree(), slab, 7).size(), 2u) << "rounds of parcels";
}

TEST(SlabField, EachSlabsPieceIsTheWholeLevelSetWithinIt) {
  // A piece kept apart: a slab's own leaves, closed alone, are the whole
  // level set clipped to the slab, tiles and nodes alike; the pieces' union
  // is the whole. A sphere wide enough to hold whole 128-wide internal nodes
  // inside (tiles one level up), and a torus, whose hole a column of leaves
  // crosses twice; cuts through internal nodes and along their faces.
  const auto shapes = {openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(150.0f, openvdb::Vec3f(20.5f, -3.2f, 7.7f), 1.0f, 3.0f),
                       sample(shapes::Torus{Vec3d(0.2, 0.1, -0.2), 12.0, 3.1}, openvdb::BBoxd(Vec3d(-18), Vec3d(18)))};
  const std::vector<openvdb::Int32> cuts{-SlabBounds::kUnbounded, -8, 0, 16, 128, SlabBounds::kUnbounded};
  for (const openvdb::FloatGrid::Ptr& shape : shapes) {
    openvdb::FloatGrid::Ptr united;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const SlabBounds slab{cuts[k], cuts[k + 1]};
      const openvdb::FloatGrid::Ptr piece = shape->copyWithNewTree();
      addLevelSetLeaves(*piece, packLevelSetLeaves(*shape, slab));
      closeLevelSetPiece(*piece);
      const openvdb::FloatGrid::Ptr clipped = test::clippedToSlab(*shape, slab);
      std::string why;
      EXPECT_TRUE(test::identical(*clipped, *piece, &why)) << "slab " << k << ": " << why;
      EXPECT_TRUE(test::sameTreeBytes(*clipped, *piece)) << "slab " << k << ": the trees' tiles or nodes differ";
      if (!united) united = piece->deepCopy();
      else openvdb::tools::csgUnion(united->tree(), piece->deepCopy()->tree());
    }
    std::string why;
    EXPECT_TRUE(test::identical(*shape, *united, &why)) << why;
  }
  std::size_t wideTiles = 0;  // the sphere's tiles of whole 128-wide nodes
  for (auto tile = shapes.begin()->get()->tree().cbeginValueOff(); tile; ++tile) wideTiles += tile.getLevel() == 2;
  EXPECT_GT(wideTiles, 0u);
}

TEST(SlabField, LeavesOutsideASlabAreLetGoWithoutNodesAdded) {
  // A weight grid and a colour grid along a line through several 4096-wide
  // nodes, cut down to a slab that ends inside one of them.
  openvdb::FloatGrid weight(0.0f);
  openvdb::Vec3fGrid colour(openvdb::Vec3f(0.0f));
  std::size_t within = 0;
  const SlabBounds slab{-8, 4104};
  for (openvdb::Int32 x = -5000; x < 9000; x += 3) {
    weight.tree().setValueOn(openvdb::Coord(x, 5, -7), static_cast<float>(x));
    colour.tree().setValueOn(openvdb::Coord(x, 5, -7), openvdb::Vec3f(static_cast<float>(x)));
    within += slab.contains(x & ~7);
  }
  const std::vector<openvdb::Index32> nodesBefore = weight.tree().nodeCount();
  dropLeavesOutside(weight, slab);
  dropLeavesOutside(colour, slab);
  EXPECT_EQ(weight.activeVoxelCount(), within);
  EXPECT_EQ(colour.activeVoxelCount(), within);
  for (auto v = weight.cbeginValueOn(); v; ++v) {
    EXPECT_TRUE(slab.contains(v.getCoord().x()));
    EXPECT_EQ(*v, static_cast<float>(v.getCoord().x()));
  }
  const std::vector<openvdb::Index32> nodesAfter = weight.tree().nodeCount();
  for (std::size_t level = 0; level + 1 < nodesBefore.size(); ++level)  // the root's one node aside
    EXPECT_LT(nodesAfter[level], nodesBefore[level]) << "level " << level;
  EXPECT_EQ(colour.tree().nodeCount(), nodesAfter);
}

TEST(SlabField, PiecesOfAWeightGridPutTogetherAreTheWhole) {
  openvdb::FloatGrid weight(0.0f);
  for (openvdb::Int32 x = -300; x < 300; x += 5) weight.tree().setValueOn(openvdb::Coord(x, x / 3, 7), 0.5f * x);
  std::vector<openvdb::FloatGrid::Ptr> pieces;
  for (const SlabBounds& slab : {SlabBounds{-SlabBounds::kUnbounded, 0}, SlabBounds{0, 128}, SlabBounds{128, SlabBounds::kUnbounded}}) {
    pieces.push_back(weight.deepCopy());
    dropLeavesOutside(*pieces.back(), slab);
  }
  const openvdb::FloatGrid::Ptr whole = weight.copyWithNewTree();
  for (const openvdb::FloatGrid::Ptr& piece : pieces) moveAllLeaves(*piece, *whole);
  std::string why;
  EXPECT_TRUE(test::identical(weight, *whole, &why)) << why;
  EXPECT_EQ(pieces.front()->tree().leafCount(), 0u) << "the leaves were moved";
  const openvdb::FloatGrid::Ptr again = weight.deepCopy();
  EXPECT_THROW(moveAllLeaves(*again, *whole), std::invalid_argument);
}

TEST(SlabField, LevelSetPiecesAreChecked) {
  const auto sphere = sample(shapes::Sphere{Vec3d(0.0), 6.0}, openvdb::BBoxd(Vec3d(-9), Vec3d(9)));
  const PackedLeaves all = packLevelSetLeaves(*sphere, SlabBounds{});
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.capacity(), all.size()) << "the leaves are packed into one allocation of their size";
  // A leaf two pieces hold, and a piece cut short.
  EXPECT_THROW(assembleLevelSet({all, all}, *sphere), std::invalid_argument);
  PackedLeaves truncated = all;
  truncated.pop_back();
  EXPECT_THROW(assembleLevelSet({truncated}, *sphere), std::invalid_argument);
  // A slab's piece holds only the leaves whose origin lies in it.
  SlabBounds upper;
  upper.begin = 0;
  EXPECT_LT(packLevelSetLeaves(*sphere, upper).size(), all.size());
  EXPECT_GT(packLevelSetLeaves(*sphere, upper).size(), 0u);
  // Moved leaves leave their grid and cannot be moved in twice.
  const openvdb::FloatGrid::Ptr from = sphere->deepCopy();
  const openvdb::FloatGrid::Ptr to = sphere->copyWithNewTree();
  moveLevelSetLeaves(*from, upper, *to);
  EXPECT_EQ(from->tree().leafCount() + to->tree().leafCount(), sphere->tree().leafCount());
  EXPECT_EQ(packLevelSetLeaves(*to, SlabBounds{}), packLevelSetLeaves(*sphere, upper));
  EXPECT_TRUE(packLevelSetLeaves(*from, upper).empty());
  const openvdb::FloatGrid::Ptr again = sphere->deepCopy();
  EXPECT_THROW(moveLevelSetLeaves(*again, upper, *to), std::invalid_argument);
}

TEST(SlabField, BalancedSlabsShareTheLeaves) {
  // Columns at x = 0, 8, ..., 72 with 1, 1, ..., 1, 9 leaves: two slabs split
  // the 18 leaves 9 and 9.
  std::vector<std::pair<openvdb::Int32, std::size_t>> columns;
  for (int i = 0; i < 9; ++i) columns.emplace_back(8 * i, 1);
  columns.emplace_back(72, 9);
  const std::vector<SlabBounds> two = balancedSlabs(columns, 2);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].begin, -SlabBounds::kUnbounded);
  EXPECT_EQ(two[0].end, 72);
  EXPECT_EQ(two[1].begin, 72);
  EXPECT_EQ(two[1].end, SlabBounds::kUnbounded);
  // Every slab gets a column, even when one column holds nearly everything.
  const std::vector<SlabBounds> ten = balancedSlabs(columns, 10);
  for (std::size_t k = 1; k < ten.size(); ++k) EXPECT_EQ(ten[k].begin, 8 * static_cast<int>(k));
  EXPECT_THROW(balancedSlabs(columns, 11), std::invalid_argument);
  EXPECT_THROW(balancedSlabs({{4, 1}, {12, 1}}, 2), std::invalid_argument);
}

TEST(SlabField, BoundsAndPackedLeavesAreChecked) {
  const auto sphere = sample(shapes::Sphere{Vec3d(0.0), 6.0}, openvdb::BBoxd(Vec3d(-9), Vec3d(9)));
  SlabBounds unaligned;
  unaligned.end = 3;
  EXPECT_THROW(SlabField::fromLevelSet(*sphere, unaligned), std::invalid_argument);
  SlabBounds lower, upper;
  lower.end = upper.begin = 0;
  SlabField a = SlabField::fromLevelSet(*sphere, lower);
  SlabField b = SlabField::fromLevelSet(*sphere, upper);
  PackedLeaves truncated = b.ghostsFor(SlabSide::kLower);
  ASSERT_FALSE(truncated.empty());
  truncated.pop_back();
  EXPECT_THROW(a.acceptGhosts(SlabSide::kHigher, truncated), std::invalid_argument);
  // Leaves from the wrong column are refused.
  EXPECT_THROW(a.acceptGhosts(SlabSide::kHigher, a.ghostsFor(SlabSide::kHigher)), std::invalid_argument);
  // The first slab has no lower neighbour: it sends and takes nothing there.
  EXPECT_TRUE(a.ghostsFor(SlabSide::kLower).empty());
}

}  // namespace
}  // namespace levelfuse

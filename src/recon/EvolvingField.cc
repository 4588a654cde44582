// levelfuse: the field of one grid of a reconstruction, whole or in slabs.

#include "EvolvingField.h"

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/Refine.h>

#include <utility>


namespace levelfuse::detail {

namespace {

/// This process's slab of `whole`: leaf columns shared out by their leaf counts.
SlabBounds slabOf(const SparseField& whole, const SlabTeam& team) {
  return balancedSlabs(leafColumns(whole.grid().tree()), team.size()).at(static_cast<std::size_t>(team.rank()));
}

}  // namespace

EvolvingField::EvolvingField(SparseField whole) : mWhole(std::make_unique<SparseField>(std::move(whole))) {}

EvolvingField::EvolvingField(const SparseField& whole, const SlabTeam& team)
    : mSlab(std::make_unique<SlabField>(SlabField::fromField(whole, slabOf(whole, team)))), mTeam(&team) {}

EvolvingField::EvolvingField(SlabField slab, const SlabTeam& team)
    : mSlab(std::make_unique<SlabField>(std::move(slab))), mTeam(&team) {}

EvolvingField::EvolvingField(EvolvingField&&) noexcept = default;
EvolvingField& EvolvingField::operator=(EvolvingField&&) noexcept = default;
EvolvingField::~EvolvingField() = default;

const openvdb::FloatGrid& EvolvingField::grid() const { return mSlab ? mSlab->grid() : mWhole->grid(); }

bool EvolvingField::owns(const openvdb::Coord& origin) const {
  return !mSlab || mSlab->bounds().contains(origin.x());
}

double EvolvingField::largest(double value) const { return mTeam ? mTeam->largest(value) : value; }

void EvolvingField::refine(const SparseFieldOptions& engine) {
  if (!mSlab) {
    openvdb::FloatGrid::Ptr refined = refineLevelSet(*std::move(*mWhole).toLevelSet(3.0));
    mWhole = std::make_unique<SparseField>(SparseField::fromLevelSet(std::move(refined), engine));
  } else {
    // The finer grid is cut afresh where its leaf nodes share out evenly.
    mSlab = std::make_unique<SlabField>(refineAcrossTeam(std::move(*mSlab), *mTeam, engine));
  }
  returnFreedMemory();  // the coarser grid and the refined level set, built on the worker threads' heaps
}

EvolvingField::Surface EvolvingField::release(const std::string& name, const Weigh& weigh, bool inPieces) {
  mReleasedStats = stats();
  mReleasedOwnLeaves = ownLeafNodes();
  if (!mSlab) {
    Surface whole{std::move(*mWhole).toLevelSet(3.0, name), nullptr};
    mWhole.reset();
    whole.weight = weigh(*whole.levelSet);
    return whole;
  }
  // Each process makes its slab's leaves of the level set (the whole
  // field's there once the ghosts are fresh) and weighs them; the first moves
  // its own in and adds the others' as they arrive, one parcel at a time.
  mTeam->refreshGhosts(*mSlab);
  mReleasedBounds = mSlab->bounds();
  Surface piece{std::move(*mSlab).toLevelSet(3.0, name), nullptr};
  mSlab.reset();
  returnFreedMemory();  // the slab, built on the worker threads' heaps
  piece.weight = weigh(*piece.levelSet);
  if (inPieces) return piece;
  Surface whole{piece.levelSet->copyWithNewTree(), piece.weight->copyWithNewTree()};
  // One grid at a time, each let go as soon as its leaves are out of it.
  gatherLevelSetLeaves(piece.levelSet, mReleasedBounds, *whole.levelSet, *mTeam);
  gatherLevelSetLeaves(piece.weight, mReleasedBounds, *whole.weight, *mTeam);
  if (mTeam->rank() != 0) return Surface();
  closeAssembledLevelSet(*whole.levelSet);
  return whole;
}

void EvolvingField::keepOwnPiece(openvdb::FloatGrid::Ptr& levelSet, openvdb::FloatGrid::Ptr& weight,
                                 openvdb::Vec3fGrid::Ptr& colour) const {
  if (!mTeam) {
    describeLevelSetPiece(*levelSet, 0, 1, SlabBounds{});
    return;
  }
  const openvdb::FloatGrid::Ptr piece = levelSet->copyWithNewTree();
  moveLevelSetLeaves(*levelSet, mReleasedBounds, *piece);
  levelSet.reset();
  closeLevelSetPiece(*piece);
  describeLevelSetPiece(*piece, mTeam->rank(), mTeam->size(), mReleasedBounds);
  levelSet = piece;
  if (weight) dropLeavesOutside(*weight, mReleasedBounds);
  if (colour) dropLeavesOutside(*colour, mReleasedBounds);
}

std::size_t EvolvingField::ownLeafNodes() const {
  if (mSlab) return mSlab->stats().leafNodes;
  return mWhole ? mWhole->stats().leafNodes : mReleasedOwnLeaves;
}

std::optional<SlabBounds> EvolvingField::slabBounds() const {
  if (mSlab) return mSlab->bounds();
  return std::nullopt;
}

SparseFieldStats EvolvingField::stats() const {
  if (mWhole) return mWhole->stats();
  if (!mSlab) return mReleasedStats;
  SparseFieldStats s = mSlab->stats();
  s.activeSetVoxels = mTeam->total(s.activeSetVoxels);
  s.bandVoxels = mTeam->total(s.bandVoxels);
  s.leafNodes = mTeam->total(s.leafNodes);
  return s;
}

}  // namespace levelfuse::detail

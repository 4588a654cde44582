// levelfuse: what a team of processes does together with the slabs of one
// field beyond a step: the field's leaf columns, refinement with new cuts, and
// a level set's leaves gathered at the first process.

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/SlabTeam.h>

#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

namespace levelfuse {

namespace {

using Column = std::pair<openvdb::Int32, std::size_t>;

/// A column as it travels: two 64-bit fields, no padding.
struct PackedColumn {
  std::int64_t x;
  std::uint64_t leaves;
};

PackedLeaves packColumns(const std::vector<Column>& columns) {
  PackedLeaves out;
  for (const Column& column : columns) {
    const PackedColumn c{column.first, column.second};
    detail::appendBytes(out, &c, sizeof(c));
  }
  return out;
}

/// Adds the columns of `packed` to `counts`.
void addColumns(const PackedLeaves& packed, std::map<openvdb::Int32, std::size_t>& counts) {
  if (packed.size() % sizeof(PackedColumn) != 0)
    throw std::invalid_argument("teamLeafColumns: " + std::to_string(packed.size()) +
                                " bytes are no whole number of leaf columns");
  for (std::size_t at = 0; at < packed.size(); at += sizeof(PackedColumn)) {
    PackedColumn c;
    std::memcpy(&c, packed.data() + at, sizeof(c));
    counts[static_cast<openvdb::Int32>(c.x)] += c.leaves;
  }
}

}  // namespace

std::vector<Column> teamLeafColumns(const std::vector<Column>& own, const SlabTeam& team) {
  std::vector<PackedLeaves> toEach(static_cast<std::size_t>(team.size()), packColumns(own));
  std::map<openvdb::Int32, std::size_t> counts;
  for (const PackedLeaves& packed : team.exchange(std::move(toEach))) addColumns(packed, counts);
  return {counts.begin(), counts.end()};
}

void gatherLevelSetLeaves(openvdb::FloatGrid::Ptr& piece, const SlabBounds& own, openvdb::FloatGrid& whole,
                          const SlabTeam& team, std::size_t leavesPerParcel) {
  std::vector<SlabBounds> parcels;
  if (team.rank() == 0) moveLevelSetLeaves(*piece, own, whole);
  else parcels = parcelsOf(piece->tree(), own, leavesPerParcel);
  const auto rounds = static_cast<std::size_t>(team.largest(static_cast<double>(parcels.size())));
  for (std::size_t k = 0; k < rounds; ++k)
    team.gatherEach(k < parcels.size() ? packLevelSetLeaves(*piece, parcels[k]) : PackedLeaves(), 0,
                    [&](PackedLeaves leaves) { addLevelSetLeaves(whole, leaves); });
  piece.reset();
}

SlabField refineAcrossTeam(SlabField slab, const SlabTeam& team, const SparseFieldOptions& engine) {
  // This process's share of the refined field: the whole field's where the
  // finer slab lies, once the ghosts are fresh (SlabField::toLevelSet).
  const SlabBounds own = onFinerGrid(slab.bounds());
  openvdb::FloatGrid::Ptr refined = [&] {
    SlabField coarse = std::move(slab);
    team.refreshGhosts(coarse);
    return refineLevelSet(*std::move(coarse).toLevelSet(3.0));  // the coarse slab let go as its level set is made
  }();
  const std::vector<SlabBounds> cuts =
      balancedSlabs(teamLeafColumns(leafColumns(refined->tree(), own), team), team.size());
  // The leaves for this process's own new slab are moved, not copied.
  const std::size_t me = static_cast<std::size_t>(team.rank());
  std::vector<PackedLeaves> toEach(cuts.size());
  for (std::size_t r = 0; r < cuts.size(); ++r)
    if (r != me) toEach[r] = packLevelSetLeaves(*refined, overlapOf(own, levelSetReach(cuts[r])));
  openvdb::FloatGrid::Ptr mine = refined->copyWithNewTree();
  moveLevelSetLeaves(*refined, overlapOf(own, levelSetReach(cuts[me])), *mine);
  refined.reset();
  returnFreedMemory();  // the coarse slab and the refined level set, built on the worker threads' heaps
  for (PackedLeaves& piece : team.exchange(std::move(toEach))) {
    addLevelSetLeaves(*mine, piece);
    PackedLeaves().swap(piece);
  }
  setTilesBesideLeaves(*mine);
  return SlabField::fromLevelSet(std::move(mine), cuts[me], engine);  // let go once read
}

}  // namespace levelfuse

// levelfuse: slabs of a sparse field: construction, ghosts, assembly.

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/TilesBesideLeaves.h>
#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

namespace levelfuse {

using detail::FloatLeaf;
using detail::LeafRecord;
using detail::SparseFieldState;
using detail::XRange;

namespace {

constexpr std::size_t kMaskWords = FloatLeaf::SIZE / 64;

/// Bytes of one packed leaf: origin, values, band (value mask), layers L0..LN.
std::size_t packedLeafBytes(int layers) {
  return 3 * sizeof(openvdb::Int32) + FloatLeaf::SIZE * sizeof(float) +
         (static_cast<std::size_t>(layers) + 2) * kMaskWords * sizeof(std::uint64_t);
}

void appendLeaf(PackedLeaves& out, const LeafRecord& record, int layers) {
  const openvdb::Int32 origin[3] = {record.origin.x(), record.origin.y(), record.origin.z()};
  detail::appendBytes(out, origin, sizeof(origin));
  detail::appendBytes(out, record.values, FloatLeaf::SIZE * sizeof(float));
  detail::appendBytes(out, detail::maskWords(record.leaf->getValueMask()), kMaskWords * sizeof(std::uint64_t));
  for (int i = 0; i <= layers; ++i)
    detail::appendBytes(out, detail::maskWords(record.layer[i]), kMaskWords * sizeof(std::uint64_t));
}

void requireWholeLeaves(const PackedLeaves& packed, int layers) {
  const std::size_t leafBytes = packedLeafBytes(layers);
  if (packed.size() % leafBytes != 0)
    throw std::invalid_argument("SlabField: " + std::to_string(packed.size()) +
                                " bytes of packed leaves are no whole number of leaves of " +
                                std::to_string(layers) + " layers (" + std::to_string(leafBytes) + " bytes each)");
}

/// The x origin of every leaf of `packed`.
std::vector<openvdb::Int32> packedColumns(const PackedLeaves& packed, int layers) {
  requireWholeLeaves(packed, layers);
  std::vector<openvdb::Int32> columns;
  for (std::size_t at = 0; at < packed.size(); at += packedLeafBytes(layers)) {
    openvdb::Int32 x;
    std::memcpy(&x, packed.data() + at, sizeof(x));
    columns.push_back(x);
  }
  return columns;
}

/// Adds the leaves of `packed` to the state's tree and table, with their
/// values, band and layers. The state's table must be built.
void insertLeaves(SparseFieldState& state, const PackedLeaves& packed) {
  const int layers = state.options.layers;
  const std::size_t leafBytes = packedLeafBytes(layers);
  requireWholeLeaves(packed, layers);
  for (std::size_t at = 0; at < packed.size(); at += leafBytes) {
    const std::uint8_t* p = packed.data() + at;
    openvdb::Int32 origin[3];
    std::memcpy(origin, p, sizeof(origin));
    p += sizeof(origin);
    FloatLeaf* leaf = state.tree().touchLeaf(openvdb::Coord(origin[0], origin[1], origin[2]));
    std::memcpy(leaf->buffer().data(), p, FloatLeaf::SIZE * sizeof(float));
    p += FloatLeaf::SIZE * sizeof(float);
    detail::LeafMask band;
    std::memcpy(&detail::maskWord(band, 0), p, kMaskWords * sizeof(std::uint64_t));
    p += kMaskWords * sizeof(std::uint64_t);
    leaf->setValueMask(band);
    std::int32_t r = state.table.find(leaf->origin());
    if (r < 0) r = state.table.add(leaf);
    state.fitRecordArrays();
    LeafRecord& record = state.table[static_cast<std::size_t>(r)];
    for (int i = 0; i <= layers; ++i) {
      std::memcpy(&detail::maskWord(record.layer[i], 0), p, kMaskWords * sizeof(std::uint64_t));
      p += kMaskWords * sizeof(std::uint64_t);
    }
    state.activeCount[static_cast<std::size_t>(r)] = record.layer[0].countOn();
  }
}

/// A state without leaves with `options`, and the voxel size, transform and
/// name of `like`.
std::unique_ptr<SparseFieldState> emptyState(const SparseFieldOptions& options, const openvdb::FloatGrid& like) {
  auto state = std::make_unique<SparseFieldState>();
  state->options = options;
  state->dx = like.voxelSize()[0];
  state->background = static_cast<float>((options.layers + 0.5) * state->dx);
  state->grid = openvdb::FloatGrid::create(state->background);
  state->grid->setTransform(like.transform().copy());
  state->grid->setGridClass(openvdb::GRID_LEVEL_SET);
  state->grid->setName(like.getName());
  return state;
}

/// x origin of the column of leaves a slab shares with its `side` neighbour
/// (its own, for ghostsFor) or keeps as ghosts from it.
openvdb::Int32 ownColumn(const SlabBounds& b, SlabSide side) {
  return side == SlabSide::kLower ? b.begin : b.end - kLeafNodeWidth;
}
openvdb::Int32 ghostColumn(const SlabBounds& b, SlabSide side) {
  return side == SlabSide::kLower ? b.begin - kLeafNodeWidth : b.end;
}
bool hasNeighbour(const SlabBounds& b, SlabSide side) {
  return side == SlabSide::kLower ? b.hasLower() : b.hasHigher();
}

void requireBounds(const SlabBounds& b) {
  const bool aligned = (!hasNeighbour(b, SlabSide::kLower) || b.begin % kLeafNodeWidth == 0) &&
                       (!hasNeighbour(b, SlabSide::kHigher) || b.end % kLeafNodeWidth == 0);
  if (!aligned || b.begin >= b.end)
    throw std::invalid_argument("SlabField: a slab must own x in [begin, end) with begin < end, both multiples of " +
                                std::to_string(kLeafNodeWidth) + " voxels (got [" + std::to_string(b.begin) + ", " +
                                std::to_string(b.end) + "))");
}

/// The x ranges of a slab's own leaves and of its leaves and ghosts: one
/// column of ghosts beside each neighbour.
std::pair<XRange, XRange> ownedAndDomain(const SlabBounds& bounds) {
  requireBounds(bounds);
  XRange owned, domain;
  if (hasNeighbour(bounds, SlabSide::kLower)) {
    owned.begin = bounds.begin;
    domain.begin = ghostColumn(bounds, SlabSide::kLower);
  }
  if (hasNeighbour(bounds, SlabSide::kHigher)) {
    owned.end = bounds.end;
    domain.end = ghostColumn(bounds, SlabSide::kHigher) + kLeafNodeWidth;
  }
  return {owned, domain};
}

}  // namespace

SlabField::SlabField(std::unique_ptr<SparseFieldState> state, const SlabBounds& bounds)
    : mState(std::move(state)), mBounds(bounds) {}
SlabField::SlabField(SlabField&&) noexcept = default;
SlabField& SlabField::operator=(SlabField&&) noexcept = default;
SlabField::~SlabField() = default;

SlabField SlabField::fromLevelSet(const openvdb::FloatGrid& levelSet, const SlabBounds& bounds,
                                  const SparseFieldOptions& options) {
  const auto [owned, domain] = ownedAndDomain(bounds);
  auto state = detail::stateFromLevelSet(levelSet, options, domain);
  state->owned = owned;
  return SlabField(std::move(state), bounds);
}

SlabField SlabField::fromLevelSet(openvdb::FloatGrid::Ptr&& levelSet, const SlabBounds& bounds,
                                  const SparseFieldOptions& options) {
  const auto [owned, domain] = ownedAndDomain(bounds);
  auto state = detail::stateFromLevelSet(std::move(levelSet), options, domain);
  state->owned = owned;
  return SlabField(std::move(state), bounds);
}

SlabField SlabField::fromField(const SparseField& whole, const SlabBounds& bounds) {
  const auto [owned, domain] = ownedAndDomain(bounds);
  const SparseFieldState& from = whole.state();
  auto state = emptyState(from.options, *from.grid);
  state->domain = domain;
  state->owned = owned;
  PackedLeaves leaves;
  for (std::size_t r = 0; r < from.table.size(); ++r)
    if (from.table[r].live() && domain.contains(from.table[r].origin.x()))
      appendLeaf(leaves, from.table[r], from.options.layers);
  insertLeaves(*state, leaves);
  return SlabField(std::move(state), bounds);
}

PackedLeaves SlabField::ghostsFor(SlabSide side) const {
  PackedLeaves out;
  if (!hasNeighbour(mBounds, side)) return out;
  const openvdb::Int32 column = ownColumn(mBounds, side);
  const detail::LeafTable& table = mState->table;
  for (std::size_t r = 0; r < table.size(); ++r)
    if (table[r].live() && table[r].origin.x() == column) appendLeaf(out, table[r], mState->options.layers);
  return out;
}

void SlabField::acceptGhosts(SlabSide side, const PackedLeaves& leaves) {
  if (!hasNeighbour(mBounds, side)) return;
  const openvdb::Int32 column = ghostColumn(mBounds, side);
  SparseFieldState& state = *mState;
  for (const openvdb::Int32 x : packedColumns(leaves, state.options.layers))
    if (x != column)
      throw std::invalid_argument("SlabField::acceptGhosts: a leaf at x = " + std::to_string(x) +
                                  " is no ghost of the slab [" + std::to_string(mBounds.begin) + ", " +
                                  std::to_string(mBounds.end) + ") on that side (x = " + std::to_string(column) + ")");
  for (std::size_t r = 0; r < state.table.size(); ++r) {
    const LeafRecord& record = state.table[r];
    if (!record.live() || record.origin.x() != column) continue;
    const openvdb::Coord origin = record.origin;
    const float value = record.values[0] < 0.0f ? -state.background : state.background;
    state.table.remove(static_cast<std::int32_t>(r));
    state.activeCount[r] = 0;
    state.tree().addTile(1, origin, value, false);
  }
  insertLeaves(state, leaves);
}

double SlabField::timeStep(double maxSpeed, double curvatureWeight, double stiffness, double maxDt) const {
  return detail::chooseTimeStep(*mState, maxSpeed, curvatureWeight, stiffness, maxDt);
}

StepTally SlabField::applyRates(double dt, double maxSpeed) { return detail::applyRates(*mState, dt, maxSpeed); }

namespace {

/// A slab's level set (levelSetOf) kept within the slab's `domain`: growing
/// the band to its half-width reached past the ghosts, from layers that were
/// wrong there.
openvdb::FloatGrid::Ptr withinDomain(openvdb::FloatGrid::Ptr levelSet, const detail::XRange& domain) {
  std::vector<openvdb::Coord> beyond;
  for (auto leaf = levelSet->tree().cbeginLeaf(); leaf; ++leaf)
    if (!domain.contains(leaf->origin().x())) beyond.push_back(leaf->origin());
  for (const openvdb::Coord& origin : beyond) levelSet->tree().addTile(1, origin, levelSet->background(), false);
  setTilesBesideLeaves(*levelSet);
  return levelSet;
}

}  // namespace

openvdb::FloatGrid::Ptr SlabField::toLevelSet(double halfWidth, const std::string& name) const& {
  return withinDomain(detail::levelSetOf(*mState, halfWidth, name), mState->domain);
}

openvdb::FloatGrid::Ptr SlabField::toLevelSet(double halfWidth, const std::string& name) && {
  const detail::XRange domain = mState->domain;
  return withinDomain(detail::levelSetOf(std::move(mState), halfWidth, name), domain);
}

PackedLeaves SlabField::ownedLeaves() const {
  PackedLeaves out;
  const detail::LeafTable& table = mState->table;
  for (std::size_t r = 0; r < table.size(); ++r)
    if (mState->owns(table[r])) appendLeaf(out, table[r], mState->options.layers);
  return out;
}

SparseField SlabField::assemble(std::vector<PackedLeaves> slabs, const openvdb::FloatGrid& levelSet,
                                const SparseFieldOptions& options) {
  auto state = emptyState(options, levelSet);
  for (PackedLeaves& slab : slabs) {
    insertLeaves(*state, slab);
    PackedLeaves().swap(slab);
  }
  // The band is whole again, so the flood fill finds the side of every voxel
  // and tile beyond it.
  openvdb::tools::signedFloodFill(state->tree());
  return SparseField(std::move(state));
}

const openvdb::FloatGrid& SlabField::grid() const { return *mState->grid; }
double SlabField::voxelSize() const { return mState->dx; }
const SparseFieldOptions& SlabField::options() const { return mState->options; }
SparseFieldStats SlabField::stats() const { return detail::statsOf(*mState); }

SlabBounds onFinerGrid(const SlabBounds& bounds) {
  SlabBounds finer = bounds;
  if (finer.hasLower()) finer.begin *= 2;
  if (finer.hasHigher()) finer.end *= 2;
  return finer;
}

std::vector<std::pair<openvdb::Int32, std::size_t>> leafColumns(const openvdb::FloatTree& tree,
                                                                 const SlabBounds& within) {
  std::map<openvdb::Int32, std::size_t> counts;
  for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf)
    if (within.contains(leaf->origin().x())) ++counts[leaf->origin().x()];
  return {counts.begin(), counts.end()};
}

std::vector<SlabBounds> balancedSlabs(const std::vector<std::pair<openvdb::Int32, std::size_t>>& columns, int count,
                                      openvdb::Int32 leafWidth) {
  std::vector<std::pair<openvdb::Int32, std::size_t>> sorted;
  for (const auto& c : columns)
    if (c.second > 0) sorted.push_back(c);
  std::sort(sorted.begin(), sorted.end());
  const std::size_t slabs = static_cast<std::size_t>(std::max(count, 1));
  if (leafWidth <= 0 || leafWidth % kLeafNodeWidth != 0)
    throw std::invalid_argument("balancedSlabs: columns must be a whole number of leaf nodes wide (" +
                                std::to_string(kLeafNodeWidth) + " voxels), not " + std::to_string(leafWidth));
  for (const auto& c : sorted)
    if (c.first % leafWidth != 0)
      throw std::invalid_argument("balancedSlabs: a column's origin x = " + std::to_string(c.first) +
                                  " is not a multiple of its width " + std::to_string(leafWidth));
  if (sorted.size() < slabs)
    throw std::invalid_argument("balancedSlabs: the surface spans " + std::to_string(sorted.size()) +
                                " columns of leaf nodes, too few for " + std::to_string(slabs) +
                                " slabs: use fewer processes or a finer grid");
  std::size_t total = 0;
  for (const auto& c : sorted) total += c.second;
  std::vector<SlabBounds> out(slabs);
  std::size_t column = 0, sum = 0;
  for (std::size_t k = 0; k + 1 < slabs; ++k) {
    // Take columns until this slab has its share, leaving one for each slab after it.
    const double share = static_cast<double>(total) * static_cast<double>(k + 1) / static_cast<double>(slabs);
    do {
      sum += sorted[column].second;
      ++column;
    } while (column < sorted.size() - (slabs - k - 1) && static_cast<double>(sum) < share);
    const openvdb::Int32 cut = sorted[column].first;
    out[k].end = cut;
    out[k + 1].begin = cut;
  }
  return out;
}

}  // namespace levelfuse

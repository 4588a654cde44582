// levelfuse: construction, export and queries of the sparse field.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/Background.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/detail/LeafNeighbourhood.h>
#include <levelfuse/levelset/detail/LeafSigns.h>
#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace levelfuse {

using detail::FloatLeaf;
using detail::LeafRecord;
using detail::SparseFieldState;

namespace {

void validateOptions(const SparseFieldOptions& options) {
  if (options.layers < 2 || options.layers > detail::kMaxLayers)
    throw std::invalid_argument("SparseFieldOptions::layers must be between 2 and " +
                                std::to_string(detail::kMaxLayers) + " (the 3x3x3 kernel needs 2)");
  if (!(options.maxStepChange > 0.0 && options.maxStepChange < 0.5))
    throw std::invalid_argument("SparseFieldOptions::maxStepChange must lie in (0, 0.5) voxel");
  if (!(options.curvatureStepLimit > 0.0))
    throw std::invalid_argument("SparseFieldOptions::curvatureStepLimit must be positive");
  if (!(options.stiffnessStepLimit > 0.0))
    throw std::invalid_argument("SparseFieldOptions::stiffnessStepLimit must be positive");
}

/// Builds the state from `activeSet`, the voxels of the active set (a bit
/// each). `makeProbe()` is called per task; its Probe answers inside(ijk) for
/// any voxel, so the leaves around the layers get the right side, and
/// activeValue(ijk), the value of a voxel of the active set, in [-1/2, 1/2]
/// voxel. Leaves are made only where their origin lies in `domain`; `probed`
/// is called once no probe is made any more.
template <typename ProbeFactory>
std::unique_ptr<SparseFieldState> buildFromActiveSet(const openvdb::math::Transform& transform,
                                                     const SparseFieldOptions& options, openvdb::MaskTree&& activeSet,
                                                     const ProbeFactory& makeProbe,
                                                     const detail::XRange& domain = {},
                                                     const std::function<void()>& probed = {}) {
  auto state = std::make_unique<SparseFieldState>();
  state->options = options;
  state->domain = domain;
  state->dx = transform.voxelSize()[0];
  state->background = static_cast<float>((options.layers + 0.5) * state->dx);
  state->grid = openvdb::FloatGrid::create(state->background);
  state->grid->setTransform(transform.copy());
  state->grid->setGridClass(openvdb::GRID_LEVEL_SET);

  // Leaves for every voxel within N of the active set.
  {
    openvdb::MaskTree reach(activeSet);
    openvdb::tools::dilateActiveValues(reach, options.layers, openvdb::tools::NN_FACE,
                                       openvdb::tools::IGNORE_TILES);
    for (auto it = reach.cbeginLeaf(); it; ++it)
      if (domain.contains(it->origin().x())) state->tree().touchLeaf(it->origin());
  }
  detail::FloatTree& tree = state->tree();

  // Every voxel of those leaves starts at the background of its side, and
  // the active set at its value.
  {
    std::vector<FloatLeaf*> leaves;
    tree.getNodes(leaves);
    const float background = state->background;
    parallelFor(leaves.size(), 1, [&](std::size_t begin, std::size_t end) {
      auto probe = makeProbe();
      for (std::size_t l = begin; l != end; ++l) {
        FloatLeaf& leaf = *leaves[l];
        leaf.setValuesOff();
        float* values = leaf.buffer().data();
        for (openvdb::Index o = 0; o < FloatLeaf::SIZE; ++o)
          values[o] = probe.inside(leaf.offsetToGlobalCoord(o)) ? -background : background;
        if (const auto* active = activeSet.probeConstLeaf(leaf.origin()))
          for (auto it = active->cbeginValueOn(); it; ++it) values[it.pos()] = probe.activeValue(it.getCoord());
      }
    });
  }
  if (probed) probed();

  // The active set itself.
  state->table.build(tree);
  state->fitRecordArrays();
  for (auto active = activeSet.cbeginLeaf(); active; ++active) {
    if (!tree.probeConstLeaf(active->origin())) continue;
    LeafRecord& record = state->table[state->table.find(active->origin())];
    record.next |= active->getValueMask();
  }
  activeSet.clear();  // placed: let go before the layers are built
  detail::rebuildLayers(*state);
  openvdb::tools::signedFloodFill(tree);
  return state;
}

/// Answers inside/outside from an OpenVDB level set, one accessor per task;
/// a point of the active set keeps its value, clamped to half a voxel (where
/// both members of a crossing lie beyond it, stateOfLevelSet made the nearer
/// one active).
struct LevelSetProbe {
  openvdb::FloatGrid::ConstAccessor acc;
  float half;
  bool inside(const openvdb::Coord& ijk) const { return acc.getValue(ijk) < 0.0f; }
  float activeValue(const openvdb::Coord& ijk) const { return std::clamp(acc.getValue(ijk), -half, half); }
};

/// Answers inside/outside from a mask (active = inside), one accessor per
/// task; a point of the active set lies half a voxel from the surface.
struct MaskProbe {
  openvdb::MaskGrid::ConstAccessor acc;
  float half;
  bool inside(const openvdb::Coord& ijk) const { return acc.isValueOn(ijk); }
  float activeValue(const openvdb::Coord& ijk) const { return inside(ijk) ? -half : half; }
};

/// The active set around a mask's inside (active = inside): each inside voxel
/// next to an outside one, and that outside voxel, which lie half a voxel
/// from the surface.
openvdb::MaskTree activeSetOfMask(const openvdb::MaskGrid& inside) {
  openvdb::MaskTree activeSet;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> active(activeSet);
  openvdb::MaskGrid::ConstAccessor acc = inside.getConstAccessor();
  const auto visit = [&](const openvdb::Coord& ijk) {
    for (const auto& e : detail::kFaceOffset) {
      const openvdb::Coord n = ijk.offsetBy(e[0], e[1], e[2]);
      if (!acc.isValueOn(n)) {
        active.setValueOn(ijk);
        active.setValueOn(n);
      }
    }
  };
  for (auto it = inside.tree().cbeginValueOn(); it; ++it) {
    if (it.isVoxelValue()) {
      visit(it.getCoord());
      continue;
    }
    // An active tile: only its boundary voxels can touch the outside.
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    const openvdb::Coord lo = box.min(), hi = box.max();
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y) {
        const bool side = x == lo.x() || x == hi.x() || y == lo.y() || y == hi.y();
        if (side) {
          for (int z = lo.z(); z <= hi.z(); ++z) visit(openvdb::Coord(x, y, z));
        } else {
          visit(openvdb::Coord(x, y, lo.z()));
          visit(openvdb::Coord(x, y, hi.z()));
        }
      }
  }
  return activeSet;
}

}  // namespace

SparseField::SparseField(std::unique_ptr<SparseFieldState> state) : mState(std::move(state)) {}
SparseField::SparseField(SparseField&&) noexcept = default;
SparseField& SparseField::operator=(SparseField&&) noexcept = default;
SparseField::~SparseField() = default;

SparseField::SparseField(const SparseField& other) : mState(std::make_unique<SparseFieldState>()) {
  const SparseFieldState& from = *other.mState;
  mState->options = from.options;
  mState->dx = from.dx;
  mState->background = from.background;
  mState->grid = from.grid->deepCopy();
  mState->table.build(mState->tree());
  mState->fitRecordArrays();
  for (std::size_t r = 0; r < mState->table.size(); ++r) {
    LeafRecord& record = mState->table[r];
    const LeafRecord& source = from.table[from.table.find(record.origin)];
    record.layer = source.layer;
    mState->activeCount[r] = record.layer[0].countOn();
  }
}

SparseField& SparseField::operator=(const SparseField& other) {
  if (this != &other) *this = SparseField(other);
  return *this;
}

namespace detail {

namespace {

/// stateFromLevelSet's work; `read` is called once `levelSet` is read no more.
std::unique_ptr<SparseFieldState> stateOfLevelSet(const openvdb::FloatGrid& levelSet, const SparseFieldOptions& options,
                                                  const XRange& domain, const std::function<void()>& read) {
  validateOptions(options);
  requireLevelSet(levelSet, "SparseField::fromLevelSet");

  const float half = static_cast<float>(0.5 * levelSet.voxelSize()[0]);
  std::vector<const openvdb::FloatTree::LeafNodeType*> leaves;
  levelSet.tree().getNodes(leaves);
  leaves.erase(std::remove_if(leaves.begin(), leaves.end(),
                              [&](const auto* leaf) { return !domain.contains(leaf->origin().x()); }),
               leaves.end());
  std::vector<std::unique_ptr<openvdb::MaskTree::LeafNodeType>> found(leaves.size());
  parallelFor(leaves.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = levelSet.getConstAccessor();
    for (std::size_t l = begin; l != end; ++l) {
      const auto& leaf = *leaves[l];
      auto active = std::make_unique<openvdb::MaskTree::LeafNodeType>(leaf.origin(), false);
      // Every point on a zero crossing whose value lies in the active range
      // joins L0 (the efficient active set of the Appendix); where both
      // members of a crossing lie outside the range (a steeper function than
      // a distance), the one nearer the crossing joins, clamped. Every sign
      // change then has an active member.
      detail::forEachOn(detail::zeroCrossingVoxels(acc, leaf), [&](openvdb::Index o) {
        const float u = leaf.getValue(o);
        const openvdb::Coord local = FloatLeaf::offsetToLocalCoord(o);
        for (const auto& e : detail::kFaceOffset) {
          const float v = detail::valueBeside(acc, leaf, local, e);
          if ((u < 0.0f) != (v < 0.0f) && (std::fabs(u) <= half || std::fabs(u) <= std::fabs(v))) {
            active->setValueOn(o);
            break;
          }
        }
      });
      if (!active->isEmpty()) found[l] = std::move(active);
    }
  });
  openvdb::MaskTree activeSet;
  for (auto& leaf : found)
    if (leaf) activeSet.addLeaf(leaf.release());
  if (activeSet.empty() && domain.begin == XRange{}.begin && domain.end == XRange{}.end)
    throw std::invalid_argument("SparseField::fromLevelSet: " + describeGrid(levelSet) +
                                " has no zero crossing: there is no surface to evolve");

  const std::string name = levelSet.getName();
  auto state = buildFromActiveSet(levelSet.transform(), options, std::move(activeSet),
                                  [&] { return LevelSetProbe{levelSet.getConstAccessor(), half}; }, domain, read);
  state->grid->setName(name);
  return state;
}

}  // namespace

std::unique_ptr<SparseFieldState> stateFromLevelSet(const openvdb::FloatGrid& levelSet,
                                                    const SparseFieldOptions& options, const XRange& domain) {
  return stateOfLevelSet(levelSet, options, domain, {});
}

std::unique_ptr<SparseFieldState> stateFromLevelSet(openvdb::FloatGrid::Ptr&& levelSet,
                                                    const SparseFieldOptions& options, const XRange& domain) {
  if (!levelSet) throw std::invalid_argument("SparseField::fromLevelSet: there is no grid");
  const openvdb::FloatGrid& grid = *levelSet;
  return stateOfLevelSet(grid, options, domain, [&] { levelSet.reset(); });
}

}  // namespace detail

SparseField SparseField::fromLevelSet(const openvdb::FloatGrid& levelSet, const SparseFieldOptions& options) {
  return SparseField(detail::stateFromLevelSet(levelSet, options, detail::XRange{}));
}

SparseField SparseField::fromLevelSet(openvdb::FloatGrid::Ptr&& levelSet, const SparseFieldOptions& options) {
  return SparseField(detail::stateFromLevelSet(std::move(levelSet), options, detail::XRange{}));
}

SparseField SparseField::fromMask(const openvdb::MaskGrid& inside, const SparseFieldOptions& options) {
  validateOptions(options);
  if (const std::string problem = transformProblem(inside); !problem.empty())
    throw std::invalid_argument("SparseField::fromMask: " + problem);
  const float half = static_cast<float>(0.5 * inside.voxelSize()[0]);
  openvdb::MaskTree activeSet = activeSetOfMask(inside);
  if (activeSet.empty())
    throw std::invalid_argument("SparseField::fromMask: " + describeGrid(inside) +
                                " is empty: there is no inside to build a surface around");

  auto state = buildFromActiveSet(inside.transform(), options, std::move(activeSet),
                                  [&] { return MaskProbe{inside.getConstAccessor(), half}; });
  state->grid->setName(inside.getName());
  return SparseField(std::move(state));
}

const openvdb::FloatGrid& SparseField::grid() const { return *mState->grid; }
int SparseField::layers() const { return mState->options.layers; }
double SparseField::voxelSize() const { return mState->dx; }
const SparseFieldOptions& SparseField::options() const { return mState->options; }
void SparseField::setGrainSize(std::size_t grainSize) { mState->options.grainSize = grainSize; }

int SparseField::layerOf(const openvdb::Coord& ijk) const {
  const int outside = mState->options.layers + 1;
  const std::int32_t r = mState->table.find(ijk & ~static_cast<openvdb::Int32>(FloatLeaf::DIM - 1));
  if (r < 0) return mState->tree().getValue(ijk) < 0.0f ? -outside : outside;
  const LeafRecord& record = mState->table[r];
  const openvdb::Index o = FloatLeaf::coordToOffset(ijk);
  if (record.layer[0].isOn(o)) return 0;
  const int sign = record.leaf->getValue(o) < 0.0f ? -1 : 1;
  for (int i = 1; i <= mState->options.layers; ++i)
    if (record.layer[i].isOn(o)) return sign * i;
  return sign * outside;
}

SparseFieldStats detail::statsOf(const SparseFieldState& state) {
  SparseFieldStats s;
  const detail::LeafTable& table = state.table;
  for (std::size_t r = 0; r < table.size(); ++r) {
    if (!state.owns(table[r])) continue;
    s.activeSetVoxels += table[r].layer[0].countOn();
    s.bandVoxels += table[r].leaf->onVoxelCount();
    ++s.leafNodes;
  }
  s.memoryBytes = state.tree().memUsage() + table.memoryBytes() + state.pointValues.capacity() * sizeof(float);
  return s;
}

SparseFieldStats SparseField::stats() const { return detail::statsOf(*mState); }

openvdb::FloatGrid::Ptr SparseField::toLevelSet(double halfWidth, const std::string& name) const& {
  return detail::levelSetOf(*mState, halfWidth, name);
}

openvdb::FloatGrid::Ptr SparseField::toLevelSet(double halfWidth, const std::string& name) && {
  return detail::levelSetOf(std::move(mState), halfWidth, name);
}

namespace {

void requireHalfWidth(double halfWidth) {
  if (!(halfWidth >= 1.0))
    throw std::invalid_argument("toLevelSet: the narrow-band half-width must be at least 1 voxel");
}

/// The voxels of the outermost layers, L+-N, as a mask.
openvdb::MaskTree::Ptr outermostLayers(const detail::SparseFieldState& state) {
  auto ring = std::make_shared<openvdb::MaskTree>();
  openvdb::tree::ValueAccessor<openvdb::MaskTree> mark(*ring);
  const detail::LeafTable& table = state.table;
  const int N = state.options.layers;
  for (std::size_t r = 0; r < table.size(); ++r)
    if (table[r].live() && !table[r].layer[N].isOff()) mark.touchLeaf(table[r].origin)->setValueMask(table[r].layer[N]);
  return ring;
}

/// The origins of the leaves of `ring` and of the leaves beside them across
/// a face, sorted, each once.
std::vector<openvdb::Coord> leavesAroundRing(const openvdb::MaskTree& ring) {
  std::vector<openvdb::Coord> origins;
  origins.reserve(ring.leafCount() * (detail::kFaceCount + 1));
  for (auto leaf = ring.cbeginLeaf(); leaf; ++leaf) {
    origins.push_back(leaf->origin());
    for (int f = 0; f < detail::kFaceCount; ++f) origins.push_back(detail::leafAcross(leaf->origin(), f));
  }
  std::sort(origins.begin(), origins.end());
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
  return origins;
}

/// The voxels just beyond the band of `tree` whose outermost layer is
/// `ring`: the face neighbours of the ring's voxels outside the band, each
/// once, found leaf by leaf in parallel from the masks.
openvdb::MaskTree::Ptr facesBeyondTheBand(const openvdb::MaskTree& ring, const openvdb::FloatTree& tree) {
  const std::vector<openvdb::Coord> origins = leavesAroundRing(ring);
  std::vector<detail::LeafMask> beyond(origins.size());
  parallelFor(origins.size(), 64, [&](std::size_t begin, std::size_t end) {
    const openvdb::tree::ValueAccessor<const openvdb::MaskTree> rings(ring);
    const openvdb::tree::ValueAccessor<const openvdb::FloatTree> band(tree);
    for (std::size_t i = begin; i < end; ++i) {
      const openvdb::Coord& origin = origins[i];
      const detail::LeafMask* face[detail::kFaceCount];
      for (int f = 0; f < detail::kFaceCount; ++f) {
        const auto* leaf = rings.probeConstLeaf(detail::leafAcross(origin, f));
        face[f] = leaf ? &leaf->getValueMask() : nullptr;
      }
      const auto* self = rings.probeConstLeaf(origin);
      const detail::LeafMask grown = detail::dilateFaces(self ? self->getValueMask() : detail::LeafMask(), face);
      if (const FloatLeaf* inBand = band.probeConstLeaf(origin)) beyond[i] = grown & !inBand->getValueMask();
      else if (!band.isValueOn(origin)) beyond[i] = grown;  // an active tile holds no voxel beyond the band
    }
  });
  auto faces = std::make_shared<openvdb::MaskTree>();
  openvdb::tree::ValueAccessor<openvdb::MaskTree> mark(*faces);
  for (std::size_t i = 0; i < origins.size(); ++i)
    if (detail::anyOn(beyond[i])) mark.touchLeaf(origins[i])->setValueMask(beyond[i]);
  return faces;
}

/// The values of the voxels of `beyond` (facesBeyondTheBand) by the sparse
/// field's layer rule (LeafNeighbourhood.h) from their face neighbours in the
/// band of `tree` as it is, leaf by leaf of `beyond` in its order, each leaf's
/// in offset order; worked out in parallel.
std::vector<std::vector<float>> layerValuesBeyond(const openvdb::MaskTree& beyond, const openvdb::FloatTree& tree,
                                                  double dx) {
  const openvdb::tree::LeafManager<const openvdb::MaskTree> leaves(beyond);
  std::vector<std::vector<float>> values(leaves.leafCount());
  parallelFor(values.size(), 16, [&](std::size_t begin, std::size_t end) {
    const openvdb::tree::ValueAccessor<const openvdb::FloatTree> band(tree);
    for (std::size_t i = begin; i < end; ++i) {
      const auto& leaf = leaves.leaf(i);
      values[i].reserve(leaf.onVoxelCount());
      for (auto it = leaf.cbeginValueOn(); it; ++it) {
        const openvdb::Coord ijk = it.getCoord();
        float inner[detail::kFaceCount];
        int count = 0;
        for (const auto& e : detail::kFaceOffset) {
          const openvdb::Coord n = ijk.offsetBy(e[0], e[1], e[2]);
          if (band.isValueOn(n)) inner[count++] = band.getValue(n);
        }
        // A voxel beyond the band lies on the side of the band voxels beside it
        // (else a sign change would lie between them, and both would be in the
        // band), whatever the tiles say: a slab's tiles need not be right.
        const bool inside = inner[0] < 0.0f;
        detail::NearestInner nearest(inside);
        for (int k = 0; k < count; ++k) nearest.offer(inner[k]);
        values[i].push_back(detail::layerValue(nearest.value(), inside, static_cast<float>(dx)));
      }
    }
  });
  return values;
}

/// The band of `out` (a sparse field's values, layers L+-N of which `ring`
/// is the outermost) grown to a standard OpenVDB level set.
void growToLevelSet(openvdb::FloatGrid& out, openvdb::MaskTree::Ptr ring, int N, double dx, float background,
                    double halfWidth, const std::string& name) {
  const float width = levelSetBackground(halfWidth, dx);
  openvdb::FloatTree& tree = out.tree();

  // Grow further layers by the sparse field's own layer rule until they
  // reach the requested half-width: each voxel of a layer valued from the
  // band as it was, then all of them added.
  const int wanted = static_cast<int>(std::ceil(halfWidth - 0.5));
  openvdb::tree::ValueAccessor<openvdb::FloatTree> acc(tree);
  for (int layer = N + 1; layer <= wanted; ++layer) {
    openvdb::MaskTree::Ptr beyond = facesBeyondTheBand(*ring, tree);
    ring.reset();
    const std::vector<std::vector<float>> values = layerValuesBeyond(*beyond, tree, dx);
    std::size_t i = 0;
    for (auto leaf = beyond->cbeginLeaf(); leaf; ++leaf, ++i) {
      // A leaf the band grows into lies beyond it but for these voxels, on
      // their side (its first voxel's): its other voxels take that side's
      // background, not the tile's value (a slab's tiles need not be right).
      FloatLeaf* target = acc.probeLeaf(leaf->origin());
      if (!target) {
        target = acc.touchLeaf(leaf->origin());
        target->fill(values[i].front() < 0.0f ? -background : background, false);
      }
      std::size_t k = 0;
      for (auto it = leaf->cbeginValueOn(); it; ++it) target->setValueOn(it.pos(), values[i][k++]);
    }
    ring = std::move(beyond);
  }
  // Voxels at or past the half-width leave the band.
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(tree);
  leaves.foreach([width](openvdb::FloatTree::LeafNodeType& leaf, std::size_t) {
    for (openvdb::Index o = 0; o < FloatLeaf::SIZE; ++o) {
      const float v = leaf.getValue(o);
      if (leaf.isValueOn(o) && std::fabs(v) >= width) leaf.setValueOff(o, v < 0.0f ? -width : width);
    }
  });
  openvdb::tools::changeLevelSetBackground(tree, width);
  openvdb::tools::pruneLevelSet(tree);
  out.setGridClass(openvdb::GRID_LEVEL_SET);
  out.setName(name);
  out.insertMeta("levelfuse_layers", openvdb::Int32Metadata(N));
}

}  // namespace

openvdb::FloatGrid::Ptr detail::levelSetOf(const SparseFieldState& state, double halfWidth, const std::string& name) {
  requireHalfWidth(halfWidth);
  openvdb::FloatGrid::Ptr out = state.grid->deepCopy();
  growToLevelSet(*out, outermostLayers(state), state.options.layers, state.dx, state.background, halfWidth, name);
  return out;
}

openvdb::FloatGrid::Ptr detail::levelSetOf(std::unique_ptr<SparseFieldState> state, double halfWidth,
                                           const std::string& name) {
  requireHalfWidth(halfWidth);
  // The state's grid becomes the level set; the rest is let go first.
  openvdb::MaskTree::Ptr ring = outermostLayers(*state);
  const int N = state->options.layers;
  const double dx = state->dx;
  const float background = state->background;
  const openvdb::FloatGrid::Ptr out = std::move(state->grid);
  state.reset();
  growToLevelSet(*out, std::move(ring), N, dx, background, halfWidth, name);
  return out;
}

}  // namespace levelfuse

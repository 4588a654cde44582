// levelfuse: the linear solution, the zero set of g (section 3), as a level set.

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/Background.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/detail/LeafMaskOps.h>
#include <levelfuse/levelset/detail/LeafSigns.h>
#include <levelfuse/scan/CarvingMemo.h>
#include <levelfuse/scan/ForceField.h>

#include "CarvingVotes.h"

#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/LevelSetRebuild.h>
#include <openvdb/tree/LeafManager.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>
#include <vector>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using LeafT = openvdb::FloatTree::LeafNodeType;

/// The distance from each voxel on a zero crossing of `raw` to the zero set,
/// from where the zero set crosses the voxel's edges: along each axis on
/// which a face neighbour has the other sign, the crossing lies t = u / (u - v)
/// voxels away (linear interpolation), and the plane through the crossings
/// lies 1 / sqrt(sum 1 / t^2) voxels away. Only where the zero set crosses
/// the edges matters, not the values' scale: the weighted mean distances
/// along the lines of sight (longer than to the surface by 1 / cos of the
/// angle between sight and normal) and carving's steps (+-width) both give
/// distances to the surface, as the sparse field's active set holds them. The
/// other voxels keep their values. `raw` changes once every distance is
/// found, unless `interrupt` stops the work (Interrupted).
void distancesAtZeroCrossings(openvdb::FloatGrid& raw, const ParallelInterrupt& interrupt) {
  const float h = static_cast<float>(raw.voxelSize()[0]);
  openvdb::tree::LeafManager<openvdb::FloatTree> leaves(raw.tree());
  // The new values of each leaf's voxels on a crossing, set once all are
  // found: a quarter of a leaf's voxels where a plane cuts it, so the field
  // is not held twice.
  struct Distance {
    openvdb::Index offset;
    float value;
  };
  std::vector<std::vector<Distance>> out(leaves.leafCount());
  parallelFor(out.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = raw.getConstAccessor();
    for (std::size_t i = begin; i < end && !interrupt.stop(); ++i) {
      const LeafT& in = leaves.leaf(i);
      // Only a voxel with a neighbour of the other sign has a crossing.
      detail::forEachOn(detail::zeroCrossingVoxels(acc, in), [&](openvdb::Index o) {
        const float u = in.getValue(o);
        const Coord local = LeafT::offsetToLocalCoord(o);
        double inverseSquares = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
          double nearest = 0.0;  // the crossing's distance along the axis, in voxels; 0: none
          for (const int side : {-1, 1}) {
            int step[3] = {0, 0, 0};
            step[axis] = side;
            const float v = detail::valueBeside(acc, in, local, step);
            if ((u < 0.0f) == (v < 0.0f)) continue;
            const double t = static_cast<double>(u) / (static_cast<double>(u) - v);
            if (nearest == 0.0 || t < nearest) nearest = t;
          }
          if (nearest > 0.0) inverseSquares += 1.0 / (nearest * nearest);
        }
        if (inverseSquares > 0.0)
          out[i].push_back({o, std::copysign(static_cast<float>(h / std::sqrt(inverseSquares)), u)});
      });
    }
  });
  interrupt.throwIfStopped();
  parallelFor(out.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      for (const Distance& d : out[i]) leaves.leaf(i).setValueOnly(d.offset, d.value);
      std::vector<Distance>().swap(out[i]);
    }
  });
}

/// Components of one sign smaller than this many voxels are specks.
constexpr std::size_t kSpeckVoxels = 8;

/// True if `ijk` lies in a face-connected component of its sign of fewer
/// than kSpeckVoxels voxels; `component` is then left holding it.
bool inSpeck(const openvdb::FloatGrid::ConstAccessor& acc, const Coord& ijk, std::vector<Coord>& component) {
  const bool negative = acc.getValue(ijk) < 0.0f;
  component.assign(1, ijk);
  for (std::size_t next = 0; next < component.size(); ++next)
    for (const auto& e : detail::kFaceOffset) {
      const Coord n = component[next].offsetBy(e[0], e[1], e[2]);
      if ((acc.getValue(n) < 0.0f) != negative || std::find(component.begin(), component.end(), n) != component.end())
        continue;
      if (component.size() + 1 >= kSpeckVoxels) return false;
      component.push_back(n);
    }
  return true;
}

/// Of a leaf's voxels on a zero crossing (`crossing`), those that may lie in
/// a speck: the face-connected components of one sign within the leaf alone,
/// each flooded once, that hold fewer than kSpeckVoxels voxels (a larger one
/// is no speck, whatever lies beyond the leaf).
detail::LeafMask mayLieInSpecks(const detail::LeafMask& crossing, const detail::LeafMask& negative) {
  const detail::LeafMask positive = !negative;
  const detail::LeafMask* const withinTheLeaf[detail::kFaceCount] = {};
  detail::LeafMask open = crossing, mayLie;
  while (detail::anyOn(open)) {
    const openvdb::Index seed = open.findFirstOn();
    const detail::LeafMask& same = negative.isOn(seed) ? negative : positive;
    detail::LeafMask component;
    component.setOn(seed);
    openvdb::Index count = 1;
    for (;;) {
      const detail::LeafMask grown = detail::dilateFaces(component, withinTheLeaf) & same;
      const openvdb::Index grownCount = grown.countOn();
      if (grownCount == count) break;
      component = grown;
      count = grownCount;
    }
    if (count < kSpeckVoxels) mayLie |= component & crossing;
    open &= !component;
  }
  return mayLie;
}

/// A component of one sign smaller than 2 x 2 x 2 voxels, inside or outside,
/// cannot be told from noise on the grid: its voxels take the other sign (a
/// rebuild through a mesh leaves such specks out too). Every speck has a
/// voxel on a zero crossing, where the search starts; the specks are found on
/// the field as it is, then changed, unless `interrupt` stops the search (Interrupted).
void removeSpecks(openvdb::FloatGrid& raw, const ParallelInterrupt& interrupt) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(raw.tree());
  std::vector<std::vector<Coord>> found(leaves.leafCount());
  parallelFor(found.size(), 1, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = raw.getConstAccessor();
    std::vector<Coord> component;
    for (std::size_t i = begin; i < end && !interrupt.stop(); ++i) {
      const LeafT& leaf = leaves.leaf(i);
      const detail::LeafMask negative = detail::negativeVoxels(leaf);
      const detail::LeafMask crossing = detail::zeroCrossingVoxels(acc, leaf, negative);
      detail::forEachOn(mayLieInSpecks(crossing, negative), [&](openvdb::Index o) {
        const Coord ijk = leaf.offsetToGlobalCoord(o);
        if (inSpeck(acc, ijk, component)) found[i].insert(found[i].end(), component.begin(), component.end());
      });
    }
  });
  interrupt.throwIfStopped();
  std::vector<Coord> specks;
  for (const std::vector<Coord>& voxels : found) specks.insert(specks.end(), voxels.begin(), voxels.end());
  std::sort(specks.begin(), specks.end());
  specks.erase(std::unique(specks.begin(), specks.end()), specks.end());
  openvdb::FloatGrid::Accessor acc = raw.getAccessor();
  for (const Coord& ijk : specks) acc.setValueOnly(ijk, -acc.getValue(ijk));
}

/// The origin (in voxels) of the leaf-sized block `b`: scaled, not shifted, as
/// a left shift of a negative coordinate is undefined.
Coord blockOrigin(const Coord& b) {
  const int dim = static_cast<int>(LeafT::DIM);
  return Coord(b.x() * dim, b.y() * dim, b.z() * dim);
}

/// The blocks (leaf-node-sized cells) around the data, each outside, inside
/// or reached by the data.
class BlockClasses {
 public:
  enum : std::uint8_t { kOutside = 0, kInside = 1, kData = 2 };

  /// The blocks of `blocks` (none if it is empty), each outside.
  explicit BlockClasses(const openvdb::CoordBBox& blocks) : mBox(blocks), mDim(blocks.empty() ? Coord(0) : blocks.dim()) {
    mClass.assign(static_cast<std::size_t>(mDim.x()) * mDim.y() * mDim.z(), kOutside);
  }
  std::size_t size() const { return mClass.size(); }
  Coord block(std::size_t i) const {
    const int z = static_cast<int>(i % mDim.z()), y = static_cast<int>(i / mDim.z() % mDim.y());
    const int x = static_cast<int>(i / (static_cast<std::size_t>(mDim.z()) * mDim.y()));
    return mBox.min().offsetBy(x, y, z);
  }
  std::size_t index(const Coord& b) const {
    const Coord d = b - mBox.min();
    return (static_cast<std::size_t>(d.x()) * mDim.y() + d.y()) * mDim.z() + d.z();
  }
  std::uint8_t& operator[](std::size_t i) { return mClass[i]; }
  std::uint8_t operator[](std::size_t i) const { return mClass[i]; }
  std::uint8_t at(const Coord& b) const { return mBox.isInside(b) ? mClass[index(b)] : std::uint8_t(kOutside); }

 private:
  openvdb::CoordBBox mBox;
  Coord mDim;
  std::vector<std::uint8_t> mClass;
};

using Leaves = std::vector<std::unique_ptr<LeafT>>;
using Mask = detail::BlockVotes::Mask;

/// Votes on the voxels of the data's leaves that no window reached, from
/// those `records` kept, if any.
detail::BlockVotes votesOnUnreached(const openvdb::tree::LeafManager<const openvdb::FloatTree>& dataLeaves,
                                    double voxelSize, detail::CarvingRecords* records) {
  std::vector<Coord> origins(dataLeaves.leafCount());
  std::vector<Mask> unreached(dataLeaves.leafCount());
  for (std::size_t i = 0; i < origins.size(); ++i) {
    origins[i] = dataLeaves.leaf(i).origin();
    unreached[i] = !dataLeaves.leaf(i).getValueMask();
  }
  return detail::BlockVotes(std::move(origins), std::move(unreached), voxelSize,
                            records ? &records->blocks : nullptr);
}

/// The blocks of a slab's data (`data`, in voxels), one block beyond each
/// bounded face, in blocks along x.
std::pair<int, int> blocksOfSlab(const SlabBounds& data) {
  const int dim = static_cast<int>(LeafT::DIM);
  const auto blockOf = [dim](openvdb::Int32 x) { return static_cast<int>(std::floor(static_cast<double>(x) / dim)); };
  return {data.hasLower() ? blockOf(data.begin) - 1 : std::numeric_limits<int>::min(),
          data.hasHigher() ? blockOf(data.end - 1) + 1 : std::numeric_limits<int>::max()};
}

/// The blocks around the data (their box, one block wider), those the data
/// reach marked; of a slab's data, the whole data's box cut to the slab's
/// blocks (blocksOfSlab).
BlockClasses blocksAroundTheData(const openvdb::tree::LeafManager<const openvdb::FloatTree>& dataLeaves,
                                 const SlabOfTheData* slab) {
  openvdb::CoordBBox box;
  for (std::size_t i = 0; i < dataLeaves.leafCount(); ++i) box.expand(dataLeaves.leaf(i).origin() >> LeafT::LOG2DIM);
  if (slab) box = slab->wholeDataBlocks(box);
  box.expand(1);
  if (slab) {
    const auto [first, last] = blocksOfSlab(slab->data);
    box.min().x() = std::max(box.min().x(), first);
    box.max().x() = std::min(box.max().x(), last);
  }
  BlockClasses classes(box);
  for (std::size_t i = 0; i < dataLeaves.leafCount(); ++i)
    classes[classes.index(dataLeaves.leaf(i).origin() >> LeafT::LOG2DIM)] = BlockClasses::kData;
  return classes;
}

/// Votes on the centres of the blocks around the data that the data do not
/// reach (in the classes' order; the others are not asked), from those
/// `records` kept, if any.
detail::PointVotes votesOnBlockCentres(const BlockClasses& classes, const openvdb::math::Transform& xform,
                                       const detail::CarvingRecords* records) {
  const Coord centre(LeafT::DIM / 2);
  detail::PointVotes votes(classes.size(), [&classes, &xform, centre](std::size_t i) {
    return xform.indexToWorld(blockOrigin(classes.block(i)) + centre);
  });
  for (std::size_t i = 0; i < classes.size(); ++i) {
    if (classes[i] == BlockClasses::kData) {
      votes.skip(i);
    } else if (records) {
      const auto kept = records->centres.find(classes.block(i));
      if (kept != records->centres.end()) votes.restore(i, kept->second);
    }
  }
  return votes;
}

/// Keeps the votes on the blocks' centres in `records`.
void keepCentres(const BlockClasses& classes, const detail::PointVotes& centres, detail::CarvingRecords& records) {
  for (std::size_t i = 0; i < classes.size(); ++i)
    if (classes[i] != BlockClasses::kData) records.centres[classes.block(i)] = centres.record(i);
}

/// The blocks the data do not reach classified by carving at their centres.
void classifyBlocks(BlockClasses& classes, const detail::PointVotes& centres) {
  for (std::size_t i = 0; i < classes.size(); ++i)
    if (classes[i] != BlockClasses::kData)
      classes[i] = centres.inside(i) ? BlockClasses::kInside : BlockClasses::kOutside;
}

/// The leaves the data reach: where a window reaches, the weighted mean signed
/// distance along the lines of sight, -g / w, whose zero set is the zero set
/// of g (Eq. 17), clamped to +-width; elsewhere in them, carved.
Leaves dataLeafValues(const openvdb::tree::LeafManager<const openvdb::FloatTree>& dataLeaves,
                      const openvdb::FloatGrid& weight, const detail::BlockVotes& unreached, float width) {
  Leaves leaves(dataLeaves.leafCount());
  parallelFor(leaves.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const LeafT& g = dataLeaves.leaf(i);
      const LeafT& w = *weight.tree().probeConstLeaf(g.origin());
      auto leaf = std::make_unique<LeafT>(g.origin(), width);
      for (auto it = g.cbeginValueOn(); it; ++it)
        leaf->setValueOn(it.pos(), std::clamp(-*it / w.getValue(it.pos()), -width, width));
      unreached.forEachAsked(i, [&](openvdb::Index o, bool inside) { leaf->setValueOn(o, inside ? -width : width); });
      leaves[i] = std::move(leaf);
    }
  });
  return leaves;
}

/// The carved blocks away from the data.
struct CarvedBlocks {
  std::vector<Coord> boundary;     ///< beside a block of the other class: to be carved voxel by voxel
  std::vector<Coord> insideTiles;  ///< uniformly inside: tiles
};

/// Blocks beside a block of the other class hold the carved surface; the
/// others are uniform, and the inside ones become tiles.
CarvedBlocks boundaryBlocks(const BlockClasses& classes) {
  CarvedBlocks carved;
  for (std::size_t i = 0; i < classes.size(); ++i) {
    const std::uint8_t c = classes[i];
    if (c == BlockClasses::kData) continue;
    const Coord b = classes.block(i);
    bool differs = false;
    for (const auto& e : detail::kFaceOffset) {
      const std::uint8_t nc = classes.at(b.offsetBy(e[0], e[1], e[2]));
      if (nc != BlockClasses::kData && nc != c) differs = true;
    }
    if (differs) carved.boundary.push_back(blockOrigin(b));
    else if (c == BlockClasses::kInside) carved.insideTiles.push_back(blockOrigin(b));
  }
  return carved;
}

/// The carved leaves of the boundary blocks at `origins`, every voxel voted
/// on by `maps` (from the votes `records` kept, if any, and kept there).
Leaves carvedSurface(const std::vector<Coord>& origins, const RangeMapsFrom& maps, double margin, double voxelSize,
                     float width, const Interrupter& interrupter, detail::CarvingRecords* records) {
  Mask everyVoxel;
  everyVoxel.setOn();
  detail::BlockVotes votes(origins, std::vector<Mask>(origins.size(), everyVoxel), voxelSize,
                           records ? &records->blocks : nullptr);
  maps(votes.firstMapNeeded(), [&](std::size_t index, const RangeMap& map) {
    checkInterrupter(interrupter);
    votes.add(map, margin, index);
  });
  Leaves leaves(votes.size());
  parallelFor(leaves.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      auto leaf = std::make_unique<LeafT>(votes.origin(b), width);
      votes.forEachAsked(b, [&](openvdb::Index o, bool inside) { leaf->setValueOn(o, inside ? -width : width); });
      leaves[b] = std::move(leaf);
    }
  });
  if (records) votes.keepIn(records->blocks);
  return leaves;
}

/// The data's side of the linear solution: the blocks around the data,
/// classified, and the data's leaves with their values.
struct AroundTheData {
  BlockClasses classes;
  Leaves leaves;
};

/// Step 1 of linearSolutionField: space carving decides the voxels of the
/// data's leaves that no window reaches, and the blocks around the data, at
/// their centres (from the votes `records` kept, if any, and kept there).
AroundTheData carveAroundTheData(const AccumulatedField& field, const RangeMapsFrom& maps, double margin,
                                 float width, const Interrupter& interrupter, const SlabOfTheData* slab,
                                 detail::CarvingRecords* records) {
  const openvdb::math::Transform& xform = field.g->transform();
  const openvdb::tree::LeafManager<const openvdb::FloatTree> dataLeaves(field.g->tree());
  AroundTheData around{blocksAroundTheData(dataLeaves, slab), {}};
  detail::BlockVotes unreached = votesOnUnreached(dataLeaves, xform.voxelSize()[0], records);
  detail::PointVotes centres = votesOnBlockCentres(around.classes, xform, records);
  maps(std::min(unreached.firstMapNeeded(), centres.firstMapNeeded()), [&](std::size_t index, const RangeMap& map) {
    checkInterrupter(interrupter);
    unreached.add(map, margin, index);
    centres.add(map, margin, index);
  });
  around.leaves = dataLeafValues(dataLeaves, *field.weight, unreached, width);
  classifyBlocks(around.classes, centres);
  if (records) {
    unreached.keepIn(records->blocks);
    keepCentres(around.classes, centres, *records);
  }
  return around;
}

/// The level set the linear solution's sparse field is built from: the
/// values of step 3 below at the zero crossings (LinearBand::kZeroCrossings)
/// or rebuilt (kRebuilt); of one slab of the data, with `slab`; carving from
/// the votes `records` kept, if any, and kept there.
openvdb::FloatGrid::Ptr linearSolutionGrid(AccumulatedField field, const RangeMapsFrom& maps, double margin,
                                           LinearBand band, const Interrupter& interrupter, const SlabOfTheData* slab,
                                           detail::CarvingRecords* records = nullptr) {
  const float width = levelSetBackground(3.0, field.g->voxelSize()[0]);
  const openvdb::math::Transform::Ptr xform = field.g->transform().copy();
  const double h = xform->voxelSize()[0];

  // 1. The data's leaves and the blocks around them (carveAroundTheData).
  //    The accumulated grids are let go then: what follows needs neither.
  AroundTheData around = carveAroundTheData(field, maps, margin, width, interrupter, slab, records);
  field = AccumulatedField();
  BlockClasses& classes = around.classes;
  Leaves& leaves = around.leaves;

  // 2. Blocks beside a block of the other class hold the carved surface:
  //    carving decides their every voxel.
  CarvedBlocks carved = boundaryBlocks(classes);
  Leaves boundaryLeaves = carvedSurface(carved.boundary, maps, margin, h, width, interrupter, records);

  // 3. Together they make a field whose zero set is the linear solution, with
  //    steps where carving closes what no scan saw. (Every voxel of the leaves
  //    is active: the mesher of a rebuild sees only active ones.)
  openvdb::FloatGrid::Ptr raw = openvdb::FloatGrid::create(width);
  raw->setTransform(xform);
  raw->setGridClass(openvdb::GRID_LEVEL_SET);
  raw->setName("surface");
  for (Leaves* set : {&leaves, &boundaryLeaves})
    for (auto& leaf : *set) raw->tree().addLeaf(leaf.release());
  for (const Coord& origin : carved.insideTiles) raw->tree().addTile(1, origin, -width, false);
  if (band == LinearBand::kZeroCrossings) {
    const ParallelInterrupt interrupt(interrupter);
    removeSpecks(*raw, interrupt);
    distancesAtZeroCrossings(*raw, interrupt);
    return raw;
  }
  // 4. Rebuilt into a true narrow band of Euclidean distances.
  openvdb::FloatGrid::Ptr psi = openvdb::tools::levelSetRebuild(*raw, 0.0f, 3.0f);
  openvdb::tools::changeLevelSetBackground(psi->tree(), width);
  psi->setGridClass(openvdb::GRID_LEVEL_SET);
  return psi;
}

/// Throws std::invalid_argument unless some reading of `field` reaches a voxel.
void requireReadings(const AccumulatedField& field) {
  if (field.g->tree().leafCount() == 0)
    throw std::invalid_argument("linearSolutionField: no reading reaches any voxel");
}

/// linearSolutionField of the whole data (requireReadings checked), carving
/// from the votes `records` kept, if any, and keeping its votes there.
SparseField wholeLinearSolutionField(AccumulatedField field, const RangeMapsFrom& maps, double margin,
                                     LinearBand band, const SparseFieldOptions& engine,
                                     const Interrupter& interrupter, detail::CarvingRecords* records) {
  // The grid is let go once the field has read it.
  SparseField linear = SparseField::fromLevelSet(
      linearSolutionGrid(std::move(field), maps, margin, band, interrupter, nullptr, records), engine);
  returnFreedMemory();  // the grid and the carving's leaves, built on the worker threads' heaps
  return linear;
}

}  // namespace

SparseField linearSolutionField(AccumulatedField field, const RangeMapSequence& maps, double margin,
                                LinearBand band, const SparseFieldOptions& engine, const Interrupter& interrupter) {
  requireReadings(field);
  return wholeLinearSolutionField(std::move(field), numberedMapsOf(maps), margin, band, engine, interrupter, nullptr);
}

SparseField linearSolutionField(AccumulatedField field, const RangeMapsFrom& maps, std::size_t mapCount,
                                CarvingMemo& memo, double margin, LinearBand band, const SparseFieldOptions& engine,
                                const Interrupter& interrupter) {
  requireReadings(field);  // before the records are touched
  detail::CarvingRecords& records = memo.records();
  const std::lock_guard<std::mutex> answering(records.answering);
  records.keepOnlyFor(field.g->voxelSize()[0], margin, mapCount);
  // Votes go back to the records once complete: an interrupted answer loses
  // those it took out, and the next asks every map of their voxels again.
  return wholeLinearSolutionField(std::move(field), maps, margin, band, engine, interrupter, &records);
}

SlabField linearSolutionSlabField(AccumulatedField data, const RangeMapSequence& maps, double margin, LinearBand band,
                                  const SlabOfTheData& slab, const SlabBounds& own, const SparseFieldOptions& engine,
                                  const Interrupter& interrupter) {
  SlabField linear =
      SlabField::fromLevelSet(linearSolutionGrid(std::move(data), numberedMapsOf(maps), margin, band, interrupter, &slab),
                              own, engine);
  returnFreedMemory();  // the grid and the carving's leaves, built on the worker threads' heaps
  return linear;
}

SparseField linearSolutionField(AccumulatedField data, const std::vector<RangeMap>& maps, double margin,
                                LinearBand band, const SparseFieldOptions& engine, const Interrupter& interrupter) {
  return linearSolutionField(std::move(data), rangeMapsOf(maps), margin, band, engine, interrupter);
}

SparseField ForceField::linearSolutionField(double voxelSize, LinearBand band, const SparseFieldOptions& engine,
                                            const Interrupter& interrupter) const {
  return levelfuse::linearSolutionField(accumulate(voxelSize, interrupter), *mMaps, mWindow.reach(), band, engine,
                                        interrupter);
}

openvdb::FloatGrid::Ptr ForceField::linearSolution(double voxelSize, double halfWidth, const std::string& name,
                                                   const Interrupter& interrupter) const {
  if (!(halfWidth >= 1.0)) throw std::invalid_argument("ForceField::linearSolution: half-width below one voxel");
  return linearSolutionField(voxelSize, LinearBand::kZeroCrossings, SparseFieldOptions{}, interrupter)
      .toLevelSet(halfWidth, name);
}

}  // namespace levelfuse

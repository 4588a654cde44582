// levelfuse: the sparse field's internal state.
//
// The value tree is an ordinary OpenVDB FloatTree whose active voxels are the
// layers. Beside each of its leaf nodes a LeafRecord keeps the layer masks
// (L0 and the rings L+-i, sides told apart by the sign of the value), scratch
// masks for one step, and the indices of the 26 neighbouring leaves, so every
// parallel phase reaches across leaf faces without a tree lookup.
#pragma once

#include <levelfuse/levelset/SparseFieldOptions.h>
#include <levelfuse/levelset/SparseFieldStats.h>
#include <levelfuse/levelset/StepTally.h>
#include <levelfuse/levelset/detail/LeafMaskOps.h>

#include <levelfuse/core/Parallel.h>

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace levelfuse::detail {

using FloatTree = openvdb::FloatTree;
using FloatLeaf = FloatTree::LeafNodeType;

constexpr int kMaxLayers = 3;

/// Slot of the neighbouring leaf at leaf offset (dx, dy, dz), each in {-1, 0, 1}.
constexpr int neighbourSlot(int dx, int dy, int dz) { return (dx + 1) * 9 + (dy + 1) * 3 + (dz + 1); }
constexpr int kSelfSlot = neighbourSlot(0, 0, 0);
constexpr int kFaceSlot[kFaceCount] = {neighbourSlot(-1, 0, 0), neighbourSlot(1, 0, 0),
                                       neighbourSlot(0, -1, 0), neighbourSlot(0, 1, 0),
                                       neighbourSlot(0, 0, -1), neighbourSlot(0, 0, 1)};

struct LeafRecord {
  FloatLeaf* leaf = nullptr;  ///< null for a free record
  float* values = nullptr;    ///< the leaf's value buffer
  openvdb::Coord origin;
  std::array<std::int32_t, 27> neighbour;  ///< record index per slot, -1 where no leaf
  /// layer[0] is the active set L0; layer[i] holds L+i and L-i.
  std::array<LeafMask, kMaxLayers + 1> layer;
  // Scratch of one step.
  LeafMask up;        ///< L0 points whose new value exceeds +1/2 voxel
  LeafMask down;      ///< L0 points whose new value is below -1/2 voxel
  LeafMask conflict;  ///< of those, points adjacent to a point leaving on the other side
  LeafMask next;      ///< the new active set

  bool live() const { return leaf != nullptr; }
};

struct CoordHash {
  std::size_t operator()(const openvdb::Coord& c) const {
    return (static_cast<std::size_t>(static_cast<std::uint32_t>(c.x())) * 73856093u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(c.y())) * 19349663u) ^
           (static_cast<std::size_t>(static_cast<std::uint32_t>(c.z())) * 83492791u);
  }
};

/// The leaf records of a value tree, with neighbour links kept up to date as
/// leaves come and go. Freed records are reused; the order of records depends
/// only on the sequence of additions and removals, never on thread timing.
class LeafTable {
 public:
  /// Records for every leaf of `tree`, in the tree's (deterministic) leaf order.
  void build(FloatTree& tree);
  /// Adds a record for `leaf` and links it with its neighbours.
  std::int32_t add(FloatLeaf* leaf);
  /// Unlinks and frees record `index` (the leaf itself is not touched).
  void remove(std::int32_t index);
  /// Record index of the leaf at `origin`, or -1.
  std::int32_t find(const openvdb::Coord& origin) const;

  std::size_t size() const { return mRecords.size(); }
  LeafRecord& operator[](std::size_t i) { return mRecords[i]; }
  const LeafRecord& operator[](std::size_t i) const { return mRecords[i]; }
  std::size_t memoryBytes() const;

 private:
  std::vector<LeafRecord> mRecords;
  std::vector<std::int32_t> mFree;
  std::unordered_map<openvdb::Coord, std::int32_t, CoordHash> mIndex;
};

/// A range of x voxel indices, [begin, end): the whole line unless a field is
/// one slab of a field split along x (SlabField.h).
struct XRange {
  openvdb::Int32 begin = std::numeric_limits<openvdb::Int32>::min();
  openvdb::Int32 end = std::numeric_limits<openvdb::Int32>::max();
  bool contains(openvdb::Int32 x) const { return x >= begin && x < end; }
};

struct SparseFieldState {
  openvdb::FloatGrid::Ptr grid;  ///< values; background (N + 1/2) dx
  SparseFieldOptions options;
  LeafTable table;
  /// Where leaves may live (no leaf is allocated outside), and which leaves a
  /// step's reductions count (a slab answers for its own leaves, not for the
  /// ghosts it keeps of its neighbours'). Leaf origins are tested.
  XRange domain;
  XRange owned;
  bool owns(const LeafRecord& record) const { return record.live() && owned.contains(record.origin.x()); }
  double dx = 1.0;               ///< voxel size
  float background = 2.5f;       ///< (N + 1/2) dx
  std::vector<float> pointValues;  ///< per-active-point scratch of one step (rates)
  // Per-record numbers in compact arrays (indexed like the table), so the
  // serial bookkeeping between passes does not walk the records themselves.
  std::vector<std::uint32_t> activeCount;  ///< |L0| of each leaf
  std::vector<std::uint32_t> firstActive;  ///< each leaf's first slot in pointValues
  std::vector<std::uint8_t> atRest;         ///< leaves whose points the step's speed left at rest
  std::vector<std::uint8_t> faceRequest;   ///< faces whose missing neighbour the outermost layer needs
  std::vector<std::uint8_t> faceInside;    ///< of those, the faces whose side is the inside
  std::vector<std::uint8_t> layersSettled;  ///< leaves whose layers a step's rebuild keeps (markSettledLeaves)

  /// Sizes the per-record arrays to the table (new records start at zero).
  void fitRecordArrays() {
    activeCount.resize(table.size(), 0);
    firstActive.resize(table.size(), 0);
    atRest.resize(table.size(), 0);
    faceRequest.resize(table.size(), 0);
    faceInside.resize(table.size(), 0);
  }

  FloatTree& tree() { return grid->tree(); }
  const FloatTree& tree() const { return grid->tree(); }
};

/// Asks the cache for a leaf's values ahead of use: every phase streams the
/// band's leaves, which at R = 100 voxels already exceed a core's L2 cache.
inline void prefetchValues(const LeafRecord& record) {
  const char* r = reinterpret_cast<const char*>(&record);
  for (std::size_t line = 0; line < sizeof(LeafRecord); line += 64) __builtin_prefetch(r + line);
  if (!record.values) return;
  const char* p = reinterpret_cast<const char*>(record.values);
  for (std::size_t line = 0; line < FloatLeaf::SIZE * sizeof(float); line += 64) __builtin_prefetch(p + line);
}

/// Runs body(recordIndex) over all live records, in parallel unless grain is 0.
/// Each call may write only its own record and leaf.
template <typename Body>
void forEachRecord(const LeafTable& table, std::size_t grain, const Body& body) {
  parallelFor(table.size(), grain, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i != end; ++i) {
      if (i + 2 < end) prefetchValues(table[i + 2]);
      if (table[i].live()) body(i);
    }
  });
}

/// The state SparseField::fromLevelSet builds from `levelSet`, with leaves
/// only where their origin lies in `domain` (a slab's leaves and ghosts;
/// empty if the surface does not reach it). Throws as fromLevelSet does.
std::unique_ptr<SparseFieldState> stateFromLevelSet(const openvdb::FloatGrid& levelSet,
                                                    const SparseFieldOptions& options, const XRange& domain);
/// The same, letting go of `levelSet` once it has been read.
std::unique_ptr<SparseFieldState> stateFromLevelSet(openvdb::FloatGrid::Ptr&& levelSet,
                                                    const SparseFieldOptions& options, const XRange& domain);

/// The state's values as a standard OpenVDB level set (SparseField::toLevelSet).
openvdb::FloatGrid::Ptr levelSetOf(const SparseFieldState& state, double halfWidth, const std::string& name);
/// The same, the state let go as it is made: its grid becomes the level set's.
openvdb::FloatGrid::Ptr levelSetOf(std::unique_ptr<SparseFieldState> state, double halfWidth, const std::string& name);

/// Counts of the leaves the state answers for (all, unless it is a slab) and
/// the bytes of all it holds (SparseField::stats).
SparseFieldStats statsOf(const SparseFieldState& state);

// ---- phases shared by construction and step (SparseFieldLayers.cc) ----

/// Given the new active set in each record's `next` mask (with final values),
/// rebuilds the layers L+-1..L+-N outward by the nearest-inner-neighbour rule,
/// allocates leaves the outermost layer reaches, retires voxels that left the
/// layers, and frees leaves left without any.
void rebuildLayers(SparseFieldState& state);

/// Assigns each live record's firstActive and sizes pointValues; returns |L0|.
std::size_t indexActivePoints(SparseFieldState& state);

/// Time step for the largest speed and curvature weight (section 4.1, Eq. 31).
double chooseTimeStep(const SparseFieldState& state, double maxSpeed, double curvatureWeight, double stiffness,
                      double maxDt);

/// Adds dt times the rates in pointValues to the active values, resolves
/// conflicting moves, moves points between layers (section 5, steps 2-4);
/// returns the tally of the leaves the field answers for.
StepTally applyRates(SparseFieldState& state, double dt, double maxSpeed);

}  // namespace levelfuse::detail

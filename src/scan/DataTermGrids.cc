// levelfuse: the data term accumulated on grids binned by line of sight.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/levelset/LeafNodeWidth.h>
#include <levelfuse/scan/DataTermGrids.h>

#include "CellCorners.h"
#include "CellSpans.h"
#include "LeavesReached.h"
#include "ReadingWeight.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace levelfuse {

namespace detail {

using FloatLeaf = openvdb::FloatTree::LeafNodeType;
using VectorLeaf = openvdb::Vec3fTree::LeafNodeType;
using MaskLeaf = openvdb::Int32Tree::LeafNodeType;

/// One range map's term at one voxel of a leaf.
struct VoxelTerm {
  std::uint16_t offset;  ///< within the leaf
  std::uint8_t bin;
  float g, weight;
  openvdb::Vec3f gradient;  ///< weight * grad D, world
};

/// One range map's sums over a leaf's terms, per bin: S_b, and the sums of
/// the weights and of the windows.
struct LeafSums {
  std::array<openvdb::Vec3f, kSightBins> sight;
  std::array<openvdb::Vec2d, kSightBins> weightAndWindows;
};

/// One range map's terms at a batch of leaves, per leaf.
struct BatchTerms {
  explicit BatchTerms(std::size_t count) : terms(count), binsOfLeaf(count, 0), evaluations(count, 0), leafSums(count) {}
  std::vector<std::vector<VoxelTerm>> terms;
  std::vector<std::uint16_t> binsOfLeaf;  ///< bit b: a term of bin b
  std::vector<std::size_t> evaluations;   ///< the voxels whose terms were evaluated
  std::vector<LeafSums> leafSums;
};
static_assert(kSightBins <= 16, "a bit per bin");

/// The leaves of one bin that a leaf's terms go into, and the values of the
/// first three, which the terms are added to in place.
struct BinLeaves {
  FloatLeaf* g = nullptr;
  FloatLeaf* weight = nullptr;
  VectorLeaf* gradient = nullptr;
  float* gValues = nullptr;
  float* weightValues = nullptr;
  openvdb::Vec3f* gradientValues = nullptr;
  VectorLeaf* sight = nullptr;  ///< holds the leaf's S_b at `sightOffset`
  FloatLeaf* leafWeight = nullptr;
  FloatLeaf* leafWindows = nullptr;
  openvdb::Index sightOffset = 0;
};

/// The leaves of the grids that a batch's terms go into, per leaf: those of
/// each bin it has terms of (none of the others), and the bin mask's.
struct BatchTargets {
  explicit BatchTargets(std::size_t count) : bins(count), maskLeaves(count, nullptr) {}
  std::vector<std::array<BinLeaves, kSightBins>> bins;
  std::vector<MaskLeaf*> maskLeaves;
};

}  // namespace detail

namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using openvdb::Vec3f;
using detail::BatchTargets;
using detail::BatchTerms;
using detail::BinLeaves;
using detail::FloatLeaf;
using detail::LeafSums;
using detail::MaskLeaf;
using detail::VectorLeaf;
using detail::VoxelTerm;

/// Room made for a cube's terms before they are counted: a quarter of its 64
/// voxels (the 500 7-Scenes frames at 10 mm make one term for 4.4 voxels visited).
constexpr std::size_t kTermsPerCube = 16;

template <typename GridT>
typename GridT::Ptr emptyGrid(double voxelSize, const char* name) {
  typename GridT::Ptr grid = GridT::create();
  grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->setName(name);
  return grid;
}

/// The bin of the lines of sight of every voxel of a leaf whose voxel
/// centres lie within `radius` of `centre` (in a map's frame), or -1 unless
/// they share one: the lines of sight from a camera or a scanner's centre are
/// the directions of the voxels, which lie in the round cone of the ball.
int commonBinOfLeaf(const RangeMap& map, const Vec3d& centre, double radius) {
  if (!map.raysFromOneCentre() || map.hasRayDirections()) return -1;
  const double distance = centre.length();
  if (!(distance > radius)) return -1;
  return sightBinOfRoundCone(map.mapToWorld().transform3x3(centre / distance), radius / distance);
}

/// One range map's terms at the voxels of a leaf (Eqs. 17, 38) and their
/// sums per bin, with what the map's leaves share worked out once.
class LeafTermsOfMap {
 public:
  LeafTermsOfMap(const RangeMap& map, const detail::CellSpans& cells, const detail::UsableSpans& spans,
                 double voxelSize, const DataWindow& window, double positionVariance)
      : mMap(map),
        mCells(cells),
        mSpans(spans),
        mWindow(window),
        mPositionVariance(positionVariance),
        mReach(window.reach()),
        mH(voxelSize),
        mToMap(map.worldToMap()),
        mToWorld(map.mapToWorld()),
        mStep{mToMap.transform3x3(Vec3d(mH, 0, 0)), mToMap.transform3x3(Vec3d(0, mH, 0)),
              mToMap.transform3x3(Vec3d(0, 0, mH))},
        // Parallel rays: one line of sight, one bin.
        mParallel(!map.raysFromOneCentre() && !map.hasRayDirections()),
        mParallelBin(sightBin(mToWorld.transform3x3(Vec3d(0, 0, 1)))),
        mLeafCentre((mStep[0] + mStep[1] + mStep[2]) * (0.5 * (kLeafNodeWidth - 1))),
        // A map's frame is the world's turned: the ball's radius, with room for rounding.
        mLeafRadius(detail::cubeBallRadius(voxelSize, kLeafNodeWidth) * (1.0 + 1e-9)) {}

  /// The terms of leaf l of the batch (at `leaves[l]`) into `batch`, along
  /// the map's own rays (its projection's visit); `s` is scratch. Inlined
  /// into the loop over a task's leaves, as is the map's interpolation into
  /// it: the hot loop of integration.
  template <typename Rays>
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  void evaluate(const Rays& rays, const Coord* leaves, std::size_t l, RangeMap::LocalSample& s,
                BatchTerms& batch) const {
    if (!detail::leafMayBeReached(mSpans, leaves[l], mH, mReach)) return;
    const std::uint8_t cubes = detail::leafCubesMayBeReached(mSpans, leaves[l], mH, mReach);
    if (cubes == 0) return;
    const Vec3d base = mToMap.transform(leaves[l].asVec3d() * mH);
    const int leafBin = mParallel ? mParallelBin : commonBinOfLeaf(mMap, base + mLeafCentre, mLeafRadius);
    std::vector<VoxelTerm>& out = batch.terms[l];
    out.reserve(kTermsPerCube * static_cast<std::size_t>(openvdb::util::CountOn(cubes)));
    LeafSums& sums = batch.leafSums[l];
    sums.sight.fill(Vec3f(0.0f));
    sums.weightAndWindows.fill(openvdb::Vec2d(0.0));
    std::uint16_t& binsOfLeaf = batch.binsOfLeaf[l];
    std::size_t& evaluations = batch.evaluations[l];
    for (int i = 0; i < kLeafNodeWidth; ++i)
      for (int j = 0; j < kLeafNodeWidth; ++j) {
        // The row's two halves along z (voxels 0 to 3 and 4 to 7) lie in two cubes.
        const int cubeRow = ((i >> 2) << 2) | ((j >> 2) << 1);
        if (!(cubes & (3 << cubeRow))) continue;
        Vec3d q = base + mStep[0] * i + mStep[1] * j;
        const int row = (i << 6) | (j << 3);
        for (int k = 0; k < kLeafNodeWidth; ++k, q += mStep[2]) {
          if (!(cubes & (1 << (cubeRow | (k >> 2))))) continue;
          ++evaluations;
          if (!sample(rays, q, s)) continue;
          const double w = mWindow(s.D);
          if (w == 0.0) continue;
          const double weight = detail::readingWeight(w, s, mPositionVariance);  // Eq. 38
          const Vec3d sight = rotatedToWorld(s.lineOfSight);
          const int bin = leafBin >= 0 ? leafBin : sightBin(sight);
          binsOfLeaf = static_cast<std::uint16_t>(binsOfLeaf | (1u << bin));
          out.push_back(VoxelTerm{static_cast<std::uint16_t>(row + k), static_cast<std::uint8_t>(bin),
                                  static_cast<float>(weight * s.D),  // Eq. 17
                                  static_cast<float>(weight), Vec3f(rotatedToWorld(s.gradD) * weight)});
          sums.sight[bin] += Vec3f(sight * weight);
          sums.weightAndWindows[bin] += openvdb::Vec2d(static_cast<float>(weight), static_cast<float>(w));
        }
      }
  }

 private:
  /// The map's sample at the voxel at q (map frame): RangeMap::sampleLocal.
  template <typename Rays>
  bool sample(const Rays& rays, const Vec3d& q, RangeMap::LocalSample& s) const {
    return mMap.sampleLocal(rays, q, mReach, s);
  }
  /// A camera's voxel whose depth lies beyond the reach of every reading of
  /// its cell is culled before the interpolation, which would reject it.
  bool sample(const PinholeRays& rays, const Vec3d& q, RangeMap::LocalSample& s) const {
    if (!rays.canProject(q)) return false;
    const openvdb::math::Vec2d uv = rays.pixelOf(q);
    return mCells.mayReach(uv.x(), uv.y(), q.z(), mReach) && mMap.sampleLocalAtPixel(rays, q, uv, mReach, s);
  }
  /// A vector of the map's frame in the world's: mapToWorld().transform3x3,
  /// its sums in the same order, inlined.
  Vec3d rotatedToWorld(const Vec3d& v) const {
    const openvdb::math::Mat4d& m = mToWorld;
    return Vec3d(v[0] * m(0, 0) + v[1] * m(1, 0) + v[2] * m(2, 0), v[0] * m(0, 1) + v[1] * m(1, 1) + v[2] * m(2, 1),
                 v[0] * m(0, 2) + v[1] * m(1, 2) + v[2] * m(2, 2));
  }

  const RangeMap& mMap;
  const detail::CellSpans& mCells;
  const detail::UsableSpans& mSpans;
  const DataWindow& mWindow;
  const double mPositionVariance, mReach, mH;
  const openvdb::math::Mat4d& mToMap;
  const openvdb::math::Mat4d& mToWorld;
  const Vec3d mStep[3];
  const bool mParallel;
  const int mParallelBin;
  const Vec3d mLeafCentre;    ///< from a leaf's first voxel to its centre (map frame)
  const double mLeafRadius;  ///< from a leaf's centre to its farthest voxel
};

/// Adds each term of the batch to its voxel in its bin's grids and sets the
/// bin's bit in the mask, each leaf by one task: deterministic.
void addVoxelTerms(const BatchTerms& batch, const BatchTargets& targets, std::size_t grainSize) {
  parallelFor(batch.terms.size(), grainSize, [&](std::size_t begin, std::size_t end) {
    for (std::size_t l = begin; l < end; ++l) {
      for (const VoxelTerm& t : batch.terms[l]) {
        const BinLeaves& target = targets.bins[l][t.bin];
        const openvdb::Index o = t.offset;
        target.gValues[o] += t.g;
        target.weightValues[o] += t.weight;
        target.gradientValues[o] += t.gradient;
        target.g->getValueMask().setOn(o);
        target.weight->getValueMask().setOn(o);
        target.gradient->getValueMask().setOn(o);
        targets.maskLeaves[l]->setValueOn(o, targets.maskLeaves[l]->getValue(o) | (1 << t.bin));
      }
    }
  });
}

/// Adds each leaf's sums per bin (S_b and the sums of the weights and of the
/// windows) to the voxel of the sight grids that stands for the leaf,
/// serially: many leaves share a leaf of those grids.
void addLeafSums(const BatchTerms& batch, const BatchTargets& targets) {
  for (std::size_t l = 0; l < batch.terms.size(); ++l)
    for (std::size_t b = 0; b < kSightBins; ++b) {
      const BinLeaves& target = targets.bins[l][b];
      if (!target.sight) continue;
      const LeafSums& sums = batch.leafSums[l];
      const openvdb::Index o = target.sightOffset;
      target.sight->setValueOn(o, target.sight->getValue(o) + sums.sight[b]);
      target.leafWeight->setValueOn(o, static_cast<float>(target.leafWeight->getValue(o) + sums.weightAndWindows[b][0]));
      target.leafWindows->setValueOn(o, static_cast<float>(target.leafWindows->getValue(o) + sums.weightAndWindows[b][1]));
    }
}

}  // namespace

DataTermGrids::DataTermGrids(double voxelSize, const DataWindow& window, double positionVariance, std::size_t grainSize)
    : mVoxelSize(voxelSize), mWindow(window), mPositionVariance(positionVariance), mGrainSize(grainSize) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
    throw std::invalid_argument("DataTermGrids: the voxel size must be positive and finite");
  if (!(positionVariance >= 0.0) || !std::isfinite(positionVariance))
    throw std::invalid_argument("DataTermGrids: the position variance must be finite and not negative");
  for (Bin& bin : mBins) {
    bin.g = emptyGrid<openvdb::FloatGrid>(voxelSize, "g");
    bin.weight = emptyGrid<openvdb::FloatGrid>(voxelSize, "weight");
    bin.gradient = emptyGrid<openvdb::Vec3fGrid>(voxelSize, "gradient");
    bin.sight = emptyGrid<openvdb::Vec3fGrid>(voxelSize * kLeafNodeWidth, "sight");
    bin.leafWeight = emptyGrid<openvdb::FloatGrid>(voxelSize * kLeafNodeWidth, "leaf_weight");
    bin.leafWindows = emptyGrid<openvdb::FloatGrid>(voxelSize * kLeafNodeWidth, "leaf_windows");
  }
  mBinMask = emptyGrid<openvdb::Int32Grid>(voxelSize, "sight_bins");
}

void DataTermGrids::restrictToSlab(openvdb::Int32 begin, openvdb::Int32 end) {
  if (!(begin < end))
    throw std::invalid_argument("DataTermGrids::restrictToSlab: the slab [" + std::to_string(begin) + ", " +
                                std::to_string(end) + ") holds no voxel");
  mSlabBegin = begin;
  mSlabEnd = end;
}

void DataTermGrids::integrate(const RangeMap& map) {
  const detail::CellSpans cells(map);
  const detail::UsableSpans spans(cells);
  std::vector<Coord> leaves = detail::leavesReached(map, mVoxelSize, mWindow.reach());
  leaves.erase(std::remove_if(leaves.begin(), leaves.end(),
                              [&](const Coord& origin) { return origin.x() < mSlabBegin || origin.x() >= mSlabEnd; }),
               leaves.end());
  // A batch of leaves at a time, in order: the terms of one batch are held at
  // once, not the map's, and the sums are those of one pass.
  for (std::size_t begin = 0; begin < leaves.size(); begin += kLeavesPerBatch)
    integrateLeaves(map, cells, spans, leaves.data() + begin, std::min(kLeavesPerBatch, leaves.size() - begin));
  ++mMapCount;
}

void DataTermGrids::integrateLeaves(const RangeMap& map, const detail::CellSpans& cells,
                                    const detail::UsableSpans& spans, const Coord* leaves, std::size_t count) {
  // 1. Per leaf, the map's terms at its voxels and their sums per bin.
  const LeafTermsOfMap termsOfMap(map, cells, spans, mVoxelSize, mWindow, mPositionVariance);
  BatchTerms batch(count);
  parallelFor(count, mGrainSize, [&](std::size_t begin, std::size_t end) {
    RangeMap::LocalSample s;
    // The map's kind of rays told apart once per task, not at every voxel.
    map.projection().visit([&](const auto& rays) {
      for (std::size_t l = begin; l < end; ++l) termsOfMap.evaluate(rays, leaves, l, s, batch);
    });
  });
  // 2. The leaves that receive terms, created serially (tree topology).
  const BatchTargets targets = touchTargetLeaves(batch, leaves);
  // 3. The terms added in, each leaf by one task: deterministic.
  addVoxelTerms(batch, targets, mGrainSize);
  // 4. S_b of each leaf, serially: many leaves share a leaf of the sight grids.
  addLeafSums(batch, targets);

  for (std::size_t e : batch.evaluations) mEvaluations += e;
}

detail::BatchTargets DataTermGrids::touchTargetLeaves(const detail::BatchTerms& batch, const Coord* leaves) {
  BatchTargets targets(batch.terms.size());
  // Each bin's grids, and the mask, are trees of their own: a task each
  // touches its trees' leaves, in the leaves' order.
  parallelFor(kSightBins + 1, 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t task = begin; task < end; ++task) {
      if (task == kSightBins) touchMaskLeaves(batch, leaves, targets);
      else touchBinLeaves(task, batch, leaves, targets);
    }
  });
  return targets;
}

void DataTermGrids::touchMaskLeaves(const detail::BatchTerms& batch, const Coord* leaves,
                                    detail::BatchTargets& targets) {
  openvdb::tree::ValueAccessor<openvdb::Int32Tree, false> mask(mBinMask->tree());  // one task's: not registered
  for (std::size_t l = 0; l < batch.terms.size(); ++l)
    if (!batch.terms[l].empty()) targets.maskLeaves[l] = mask.touchLeaf(leaves[l]);
}

void DataTermGrids::touchBinLeaves(std::size_t b, const detail::BatchTerms& batch, const Coord* leaves,
                                   detail::BatchTargets& targets) {
  Bin& bin = mBins[b];
  for (std::size_t l = 0; l < batch.terms.size(); ++l) {
    if (!(batch.binsOfLeaf[l] & (1u << b))) continue;
    BinLeaves& target = targets.bins[l][b];
    target.g = bin.g->tree().touchLeaf(leaves[l]);
    target.weight = bin.weight->tree().touchLeaf(leaves[l]);
    target.gradient = bin.gradient->tree().touchLeaf(leaves[l]);
    target.gValues = target.g->buffer().data();
    target.weightValues = target.weight->buffer().data();
    target.gradientValues = target.gradient->buffer().data();
    const Coord block = detail::leafBlockOf(leaves[l]);
    target.sight = bin.sight->tree().touchLeaf(block);
    target.leafWeight = bin.leafWeight->tree().touchLeaf(block);
    target.leafWindows = bin.leafWindows->tree().touchLeaf(block);
    target.sightOffset = VectorLeaf::coordToOffset(block);
  }
}

DataTermGrids::Sampler DataTermGrids::sampler() const { return Sampler(*this); }

DataTermGrids::Sampler::Sampler(const DataTermGrids& grids) : mGrids(&grids), mMask(grids.mBinMask->tree()) {}

DataTermGrids::Sampler::BinAccess::BinAccess(const Bin& bin)
    : g(bin.g->tree()),
      weight(bin.weight->tree()),
      gradient(bin.gradient->tree()),
      sight(bin.sight->tree()),
      leafWeight(bin.leafWeight->tree()),
      leafWindows(bin.leafWindows->tree()) {}

DataTermGrids::Sampler::BinAccess& DataTermGrids::Sampler::bin(int b) {
  std::optional<BinAccess>& access = mBins[static_cast<std::size_t>(b)];
  if (!access) access.emplace(mGrids->mBins[static_cast<std::size_t>(b)]);
  return *access;
}

template <typename Visit>
void DataTermGrids::Sampler::forEachBinAround(const Vec3d& x, const Visit& visit) {
  const detail::CellCorners c = detail::cellCornersAround(x, mGrids->mVoxelSize);
  const detail::CornerValues binsAt(mMask, c);
  std::int32_t masks[8], bins = 0;
  for (int k = 0; k < 8; ++k) bins |= masks[k] = binsAt[k];
  for (int b = 0; bins != 0; ++b, bins >>= 1)
    if (bins & 1) visit(bin(b), b, c, masks);
}

namespace {

/// One bin's sums of weights and of windows over the leaves around x,
/// interpolated like its other terms: their ratio is the weight R_b of one
/// reading near x, and a weight W_b there holds N_b = W_b / R_b readings.
class LeafReadingSums {
 public:
  /// Adds a corner's leaf, with sums `weight` and `windows`, with trilinear weight t.
  void add(float weight, float windows, double t) {
    mWeightSum += t * weight;
    mWindowSum += t * windows;
  }
  double readingsIn(double weight) const { return mWeightSum > 0.0 ? weight * mWindowSum / mWeightSum : 0.0; }

 private:
  double mWeightSum = 0.0, mWindowSum = 0.0;
};

}  // namespace

DataTerms DataTermGrids::Sampler::facingTerms(const Vec3d& x, const Vec3d& normal) {
  DataTerms sum;
  forEachBinAround(x, [&](BinAccess& bin, int b, const detail::CellCorners& c, const std::int32_t(&masks)[8]) {
    const auto holds = [&](int k) { return (masks[k] & (1 << b)) && c.t[k] != 0.0; };
    // The bin's lines of sight at x first: a bin whose readings do not face
    // the normal adds nothing (Eq. 37, per bin), and its terms are not read.
    const detail::CornerLeafValues sight(bin.sight, c);
    Vec3d S(0.0);
    for (int k = 0; k < 8; ++k)
      if (holds(k)) S += c.t[k] * Vec3d(sight[k]);
    if (!(S.dot(normal) < 0.0)) return;
    const detail::CornerValues g(bin.g, c), weight(bin.weight, c);
    const detail::CornerValues gradient(bin.gradient, c);
    const detail::CornerLeafValues leafWeight(bin.leafWeight, c), leafWindows(bin.leafWindows, c);
    LeafReadingSums leafSums;
    double G = 0.0, W = 0.0;
    for (int k = 0; k < 8; ++k) {
      if (!holds(k)) continue;
      G += c.t[k] * (g[k] + Vec3d(gradient[k]).dot(c.offset[k]));  // carried to x
      W += c.t[k] * weight[k];
      leafSums.add(leafWeight[k], leafWindows[k], c.t[k]);
    }
    sum += DataTerms{G, W, leafSums.readingsIn(W)};
  });
  return sum;
}

DataTerms DataTermGrids::Sampler::allTerms(const Vec3d& x) {
  DataTerms sum;
  forEachBinAround(x, [&](BinAccess& bin, int, const detail::CellCorners& c, const std::int32_t(&)[8]) {
    const detail::CornerValues weight(bin.weight, c);
    const detail::CornerLeafValues leafWeight(bin.leafWeight, c), leafWindows(bin.leafWindows, c);
    LeafReadingSums leafSums;
    double W = 0.0;
    for (int k = 0; k < 8; ++k) {
      W += c.t[k] * weight[k];
      leafSums.add(leafWeight[k], leafWindows[k], c.t[k]);
    }
    sum += DataTerms{0.0, W, leafSums.readingsIn(W)};
  });
  return sum;
}

DataTerms DataTermGrids::facingTerms(const Vec3d& x, const Vec3d& normal) const {
  return sampler().facingTerms(x, normal);
}

double DataTermGrids::weight(const Vec3d& x) const { return sampler().weight(x); }

double DataTermGrids::readings(const Vec3d& x) const { return sampler().readings(x); }

namespace {

/// The bits of a leaf mask's word (the 64 voxels of one x) for y in [y0, y1] and z in [z0, z1].
std::uint64_t wordBits(int y0, int y1, int z0, int z1) {
  const std::uint64_t row = ((std::uint64_t(1) << (z1 - z0 + 1)) - 1) << z0;
  std::uint64_t bits = 0;
  for (int y = y0; y <= y1; ++y) bits |= row << (y * kLeafNodeWidth);
  return bits;
}

/// Whether a tree holds an active voxel or an active tile in `box`.
bool anyActiveIn(const openvdb::Int32Tree& tree, const openvdb::CoordBBox& box) {
  openvdb::tree::ValueAccessor<const openvdb::Int32Tree, false> acc(tree);
  const Coord first = detail::leafBlockOf(box.min()), last = detail::leafBlockOf(box.max());
  for (int bx = first.x(); bx <= last.x(); ++bx)
    for (int by = first.y(); by <= last.y(); ++by)
      for (int bz = first.z(); bz <= last.z(); ++bz) {
        const Coord origin(bx * kLeafNodeWidth, by * kLeafNodeWidth, bz * kLeafNodeWidth);
        const MaskLeaf* leaf = acc.probeConstLeaf(origin);
        if (!leaf) {
          if (acc.isValueOn(origin)) return true;
          continue;
        }
        const Coord lo = openvdb::Coord::maxComponent(box.min(), origin) - origin;
        const Coord hi = openvdb::Coord::minComponent(box.max(), origin.offsetBy(kLeafNodeWidth - 1)) - origin;
        const std::uint64_t bits = wordBits(lo.y(), hi.y(), lo.z(), hi.z());
        for (int x = lo.x(); x <= hi.x(); ++x)
          if (leaf->getValueMask().getWord<std::uint64_t>(static_cast<openvdb::Index>(x)) & bits) return true;
      }
  return false;
}

}  // namespace

bool DataTermGrids::mayHaveTermsIn(const openvdb::BBoxd& world) const {
  // The voxels whose terms reach a point of the box (its eight voxels around,
  // cornersAround), and one more on each side for rounding.
  const Coord lo = Coord::floor(world.min() / mVoxelSize).offsetBy(-1);
  const Coord hi = Coord::floor(world.max() / mVoxelSize).offsetBy(2);
  return anyActiveIn(mBinMask->tree(), openvdb::CoordBBox(lo, hi));
}

namespace {

/// The sum over the bins of one of their grids, voxel by voxel, in bin order.
openvdb::FloatGrid::Ptr sumOverBins(const std::vector<const openvdb::FloatGrid*>& grids, double voxelSize,
                                    const char* name) {
  openvdb::FloatGrid::Ptr total = emptyGrid<openvdb::FloatGrid>(voxelSize, name);
  openvdb::tree::ValueAccessor<openvdb::FloatTree> out(total->tree());
  for (const openvdb::FloatGrid* grid : grids)
    for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
      FloatLeaf* target = out.touchLeaf(leaf->origin());
      for (auto it = leaf->cbeginValueOn(); it; ++it)
        target->setValueOn(it.pos(), target->getValue(it.pos()) + *it);
    }
  return total;
}

}  // namespace

openvdb::FloatGrid::Ptr DataTermGrids::gGrid() const {
  std::vector<const openvdb::FloatGrid*> grids;
  for (const Bin& bin : mBins) grids.push_back(bin.g.get());
  return sumOverBins(grids, mVoxelSize, "g");
}

openvdb::FloatGrid::Ptr DataTermGrids::weightGrid() const {
  std::vector<const openvdb::FloatGrid*> grids;
  for (const Bin& bin : mBins) grids.push_back(bin.weight.get());
  return sumOverBins(grids, mVoxelSize, "weight");
}

std::size_t DataTermGrids::memoryBytes() const {
  std::size_t bytes = static_cast<std::size_t>(mBinMask->memUsage());
  for (const Bin& bin : mBins)
    bytes += static_cast<std::size_t>(bin.g->memUsage() + bin.weight->memUsage() + bin.gradient->memUsage() +
                                      bin.sight->memUsage() + bin.leafWeight->memUsage() + bin.leafWindows->memUsage());
  return bytes;
}

}  // namespace levelfuse

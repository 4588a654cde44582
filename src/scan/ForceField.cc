// levelfuse: the MAP data term (Eq. 17) and its accumulation on a sparse grid.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/scan/ForceField.h>

#include "LeavesReached.h"
#include "ReadingWeight.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using LeafT = openvdb::FloatTree::LeafNodeType;

/// The range maps whose windows reach each leaf node: the (leaf origin, map
/// index) pairs sorted by leaf and map, leaf l owning pairs [first[l], first[l + 1]).
struct MapsPerLeaf {
  std::vector<std::pair<Coord, std::uint32_t>> pairs;
  std::vector<std::size_t> first;
  std::size_t leafCount() const { return first.size() - 1; }
  const Coord& origin(std::size_t leaf) const { return pairs[first[leaf]].first; }
};

/// Which leaf nodes (of voxel size `voxelSize`) each range map's windows of
/// reach `reach` reach, gathered per leaf in map order.
MapsPerLeaf mapsPerLeaf(const std::vector<RangeMap>& maps, double voxelSize, double reach,
                        const ParallelInterrupt& interrupt) {
  std::vector<std::vector<Coord>> touched(maps.size());
  parallelFor(maps.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end && !interrupt.stop(); ++j)
      touched[j] = detail::leavesReached(maps[j], voxelSize, reach);
  });
  MapsPerLeaf out;
  for (std::size_t j = 0; j < touched.size(); ++j)
    for (const Coord& c : touched[j]) out.pairs.emplace_back(c, static_cast<std::uint32_t>(j));
  std::sort(out.pairs.begin(), out.pairs.end());
  for (std::size_t i = 0; i < out.pairs.size(); ++i)
    if (i == 0 || out.pairs[i].first != out.pairs[i - 1].first) out.first.push_back(i);
  out.first.push_back(out.pairs.size());
  return out;
}

/// A leaf node's g and weight (both null where no window reached a voxel)
/// and the (voxel, map) pairs evaluated for it.
struct LeafTerms {
  std::unique_ptr<LeafT> g, weight;
  std::size_t evaluations = 0;
};

/// Adds range map m's terms of Eq. 17 to the sums of the leaf node at
/// `origin`; returns the voxels evaluated. The leaf's depth range is first
/// held against the readings over its footprint; then voxels step through the
/// map's frame incrementally, and a voxel outside the window costs one lookup.
std::size_t addLeafTerms(const detail::UsableSpans& spans, const Coord& origin, double voxelSize,
                         const DataWindow& window, double positionVariance, std::vector<double>& gSum,
                         std::vector<double>& wSum) {
  const RangeMap& m = spans.map();
  const double reach = window.reach();
  if (!detail::leafMayBeReached(spans, origin, voxelSize, reach)) return 0;
  const int leafDim = static_cast<int>(LeafT::DIM);
  const openvdb::math::Mat4d& toMap = m.worldToMap();
  const Vec3d base = toMap.transform(origin.asVec3d() * voxelSize);
  const Vec3d step[3] = {toMap.transform3x3(Vec3d(voxelSize, 0, 0)), toMap.transform3x3(Vec3d(0, voxelSize, 0)),
                         toMap.transform3x3(Vec3d(0, 0, voxelSize))};
  RangeMap::LocalSample sample;
  // The map's kind of rays told apart once per leaf, not at every voxel.
  m.projection().visit([&](const auto& rays) {
    for (int i = 0; i < leafDim; ++i)
      for (int j = 0; j < leafDim; ++j) {
        Vec3d q = base + step[0] * i + step[1] * j;
        const std::size_t row = static_cast<std::size_t>((i << 6) | (j << 3));
        for (int k = 0; k < leafDim; ++k, q += step[2]) {
          if (!m.sampleLocal(rays, q, reach, sample)) continue;
          const double w = window(sample.D);
          if (w == 0.0) continue;
          const double weight = detail::readingWeight(w, sample, positionVariance);  // Eq. 38
          gSum[row + k] += weight * sample.D;  // Eq. 17
          wSum[row + k] += weight;
        }
      }
  });
  return LeafT::SIZE;
}

/// The leaves holding the sums, active where the weight is positive; null if none is.
std::pair<std::unique_ptr<LeafT>, std::unique_ptr<LeafT>> leafTermsOf(const Coord& origin,
                                                                       const std::vector<double>& gSum,
                                                                       const std::vector<double>& wSum) {
  auto g = std::make_unique<LeafT>(origin, 0.0f);
  auto weight = std::make_unique<LeafT>(origin, 0.0f);
  bool any = false;
  for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
    if (!(wSum[o] > 0.0)) continue;
    g->setValueOn(o, static_cast<float>(gSum[o]));
    weight->setValueOn(o, static_cast<float>(wSum[o]));
    any = true;
  }
  if (!any) return {};
  return {std::move(g), std::move(weight)};
}

/// The accumulated field of the leaves' terms: grids of voxel size `voxelSize` named "g" and "weight".
AccumulatedField fieldOf(std::vector<LeafTerms>& terms, double voxelSize) {
  AccumulatedField out;
  out.g = openvdb::FloatGrid::create(0.0f);
  out.weight = openvdb::FloatGrid::create(0.0f);
  for (auto* grid : {&out.g, &out.weight}) {
    (*grid)->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    (*grid)->setGridClass(openvdb::GRID_UNKNOWN);
  }
  out.g->setName("g");
  out.weight->setName("weight");
  for (LeafTerms& t : terms) {
    out.evaluations += t.evaluations;
    if (!t.g) continue;
    out.g->tree().addLeaf(t.g.release());
    out.weight->tree().addLeaf(t.weight.release());
  }
  return out;
}

}  // namespace

ForceFieldOptions forceFieldOptions(double epsilon, double voxelSize, WindowKind window) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
    throw std::invalid_argument("forceFieldOptions: the voxel size must be positive");
  ForceFieldOptions options;
  options.window = window;
  options.epsilon = std::max(epsilon, voxelSize);               // never narrower than a voxel of the grid
  options.positionVariance = voxelSize * voxelSize / 120.0;  // Eq. 38 with subcell positioning
  return options;
}

ForceFieldOptions defaultForceFieldOptions(const std::vector<RangeMap>& maps, double voxelSize) {
  if (maps.empty()) throw std::invalid_argument("defaultForceFieldOptions: no range maps");
  return forceFieldOptions(medianSigma(maps), voxelSize);
}

ForceField::ForceField(std::vector<RangeMap> maps, const ForceFieldOptions& options)
    : ForceField(std::make_shared<const std::vector<RangeMap>>(std::move(maps)), options) {}

ForceField::ForceField(std::shared_ptr<const std::vector<RangeMap>> maps, const ForceFieldOptions& options)
    : mMaps(std::move(maps)), mOptions(options), mWindow(options.dataWindow()) {
  if (!mMaps || mMaps->empty()) throw std::invalid_argument("ForceField: no range maps");
  if (!(mOptions.positionVariance >= 0.0)) throw std::invalid_argument("ForceField: negative position variance");
  // Where each map's windows reach, and its line of sight if it is one.
  const double reach = mWindow.reach();
  for (const RangeMap& m : *mMaps) {
    openvdb::BBoxd box = m.readingBounds();
    box.expand(reach);
    mReach.push_back(box);
    const bool parallel = !m.raysFromOneCentre() && !m.hasRayDirections();
    mParallelSight.push_back(parallel ? m.mapToWorld().transform3x3(Vec3d(0, 0, 1)) : Vec3d(0.0));
  }
}

bool ForceField::term(std::size_t j, const Vec3d& x, DataTerms& t, Vec3d* lineOfSight) const {
  RangeSample s;
  if (!(*mMaps)[j].sample(x, s)) return false;
  const double w = mWindow(s.D);
  if (w == 0.0) return false;
  const double c = 1.0 / (s.sigma * s.sigma + s.gradD.lengthSqr() * mOptions.positionVariance);  // Eq. 38
  t.weight = c * w * s.gamma;
  t.g = t.weight * s.D;  // Eq. 17
  t.readings = w;
  if (lineOfSight) *lineOfSight = s.lineOfSight;
  return true;
}

DataTerms ForceField::allTerms(const Vec3d& x) const {
  DataTerms sum, t;
  for (std::size_t j = 0; j < mMaps->size(); ++j)
    if (term(j, x, t, nullptr)) sum += t;
  return sum;
}

double ForceField::g(const Vec3d& x) const { return allTerms(x).g; }

double ForceField::weight(const Vec3d& x) const { return allTerms(x).weight; }

double ForceField::readings(const Vec3d& x) const { return allTerms(x).readings; }

double ForceField::facing(const Vec3d& x, const Vec3d& normal) const { return facingTerms(x, normal).g; }

ForceField::Terms ForceField::facingTerms(const Vec3d& x, const Vec3d& normal) const {
  Terms sum;
  const double reach = mWindow.reach();
  for (std::size_t j = 0; j < mMaps->size(); ++j) {
    if (!mReach[j].isInside(x)) continue;
    const Vec3d& sight = mParallelSight[j];
    if (sight.x() != 0.0 || sight.y() != 0.0 || sight.z() != 0.0) {
      // Parallel rays: the facing check (Eq. 37) before any lookup.
      if (!(sight.dot(normal) < 0.0)) continue;
      const RangeMap& map = (*mMaps)[j];
      RangeMap::LocalSample s;  // along the map's parallel rays, its kind known
      if (!map.sampleLocal(map.projection().parallelRays(), map.worldToMap().transform(x), reach, s)) continue;
      const double w = mWindow(s.D);
      if (w == 0.0) continue;
      const double weight = detail::readingWeight(w, s, mOptions.positionVariance);  // Eq. 38
      sum.weight += weight;
      sum.g += weight * s.D;  // Eq. 17
      sum.readings += w;
      continue;
    }
    DataTerms t;
    Vec3d los;
    if (term(j, x, t, &los) && los.dot(normal) < 0.0) sum += t;  // Eq. 37
  }
  return sum;
}

AccumulatedField ForceField::accumulate(double voxelSize, const Interrupter& interrupter) const {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
    throw std::invalid_argument("ForceField::accumulate: the voxel size must be positive");
  const ParallelInterrupt interrupt(interrupter);
  const MapsPerLeaf reaching = mapsPerLeaf(*mMaps, voxelSize, mWindow.reach(), interrupt);
  interrupt.throwIfStopped();

  // Per leaf and voxel, the terms of Eq. 17 in map order: deterministic.
  std::vector<std::unique_ptr<const detail::UsableSpans>> spans(mMaps->size());
  parallelFor(spans.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t m = begin; m < end; ++m) spans[m] = std::make_unique<const detail::UsableSpans>((*mMaps)[m]);
  });
  const std::size_t leafCount = reaching.leafCount();
  std::vector<LeafTerms> terms(leafCount);
  parallelFor(leafCount, mOptions.grainSize, [&](std::size_t begin, std::size_t end) {
    std::vector<double> gSum(LeafT::SIZE), wSum(LeafT::SIZE);
    for (std::size_t l = begin; l < end && !interrupt.stop(); ++l) {
      std::fill(gSum.begin(), gSum.end(), 0.0);
      std::fill(wSum.begin(), wSum.end(), 0.0);
      const Coord origin = reaching.origin(l);
      for (std::size_t p = reaching.first[l]; p < reaching.first[l + 1]; ++p)
        terms[l].evaluations += addLeafTerms(*spans[reaching.pairs[p].second], origin, voxelSize, mWindow,
                                             mOptions.positionVariance, gSum, wSum);
      std::tie(terms[l].g, terms[l].weight) = leafTermsOf(origin, gSum, wSum);
    }
  });
  interrupt.throwIfStopped();
  return fieldOf(terms, voxelSize);
}

}  // namespace levelfuse

// levelfuse: the MAP data term (Eq. 17) and its accumulation on a sparse grid.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/scan/ForceField.h>

#include "LeavesReached.h"
#include "ReadingWeight.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Coord;
using openvdb::Vec3d;
using LeafT = openvdb::FloatTree::LeafNodeType;

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
    const bool parallel = m.kind() == RangeMap::Kind::kOrthographic && !m.hasRayDirections();
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
      RangeMap::LocalSample s;
      if (!(*mMaps)[j].sampleLocal((*mMaps)[j].worldToMap().transform(x), reach, s)) continue;
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
  const double reach = mWindow.reach();
  const int leafDim = static_cast<int>(LeafT::DIM);

  // 1. Which leaf nodes each range map's windows reach.
  std::vector<std::vector<Coord>> touched(mMaps->size());
  const ParallelInterrupt interrupt(interrupter);
  parallelFor(mMaps->size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end && !interrupt.stop(); ++j)
      touched[j] = detail::leavesReached((*mMaps)[j], voxelSize, reach);
  });
  interrupt.throwIfStopped();

  // 2. The union, with the range maps reaching each leaf in map order.
  std::vector<std::pair<Coord, std::uint32_t>> pairs;
  for (std::size_t j = 0; j < touched.size(); ++j)
    for (const Coord& c : touched[j]) pairs.emplace_back(c, static_cast<std::uint32_t>(j));
  touched.clear();
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::size_t> firstPair;  // leaf l owns pairs [firstPair[l], firstPair[l + 1])
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (i == 0 || pairs[i].first != pairs[i - 1].first) firstPair.push_back(i);
  const std::size_t leafCount = firstPair.size();
  firstPair.push_back(pairs.size());

  // 3. Per leaf and voxel, the terms of Eq. 17 in map order: deterministic.
  //    Per (leaf, map) the leaf's depth range is first held against the
  //    readings over its footprint; then voxels step through the map's frame
  //    incrementally, and a voxel outside the window costs one lookup.
  std::vector<std::unique_ptr<LeafT>> gLeaves(leafCount), wLeaves(leafCount);
  std::vector<std::size_t> evaluations(leafCount, 0);
  const double sigmaX2 = mOptions.positionVariance;
  parallelFor(leafCount, mOptions.grainSize, [&](std::size_t begin, std::size_t end) {
    std::vector<double> gSum(LeafT::SIZE), wSum(LeafT::SIZE);
    for (std::size_t l = begin; l < end && !interrupt.stop(); ++l) {
      const Coord origin = pairs[firstPair[l]].first;
      std::fill(gSum.begin(), gSum.end(), 0.0);
      std::fill(wSum.begin(), wSum.end(), 0.0);
      for (std::size_t p = firstPair[l]; p < firstPair[l + 1]; ++p) {
        const RangeMap& m = (*mMaps)[pairs[p].second];
        const openvdb::math::Mat4d& toMap = m.worldToMap();
        const Vec3d base = toMap.transform(origin.asVec3d() * voxelSize);
        const Vec3d step[3] = {toMap.transform3x3(Vec3d(voxelSize, 0, 0)), toMap.transform3x3(Vec3d(0, voxelSize, 0)),
                               toMap.transform3x3(Vec3d(0, 0, voxelSize))};
        if (!detail::leafMayBeReached(m, origin, voxelSize, reach)) continue;
        RangeMap::LocalSample sample;
        for (int i = 0; i < leafDim; ++i)
          for (int j = 0; j < leafDim; ++j) {
            Vec3d q = base + step[0] * i + step[1] * j;
            const std::size_t row = static_cast<std::size_t>((i << 6) | (j << 3));
            for (int k = 0; k < leafDim; ++k, q += step[2]) {
              ++evaluations[l];
              if (!m.sampleLocal(q, reach, sample)) continue;
              const double w = mWindow(sample.D);
              if (w == 0.0) continue;
              const double weight = detail::readingWeight(w, sample, sigmaX2);  // Eq. 38
              gSum[row + k] += weight * sample.D;  // Eq. 17
              wSum[row + k] += weight;
            }
          }
      }
      auto gLeaf = std::make_unique<LeafT>(origin, 0.0f);
      auto wLeaf = std::make_unique<LeafT>(origin, 0.0f);
      bool any = false;
      for (openvdb::Index o = 0; o < LeafT::SIZE; ++o) {
        if (!(wSum[o] > 0.0)) continue;
        gLeaf->setValueOn(o, static_cast<float>(gSum[o]));
        wLeaf->setValueOn(o, static_cast<float>(wSum[o]));
        any = true;
      }
      if (any) {
        gLeaves[l] = std::move(gLeaf);
        wLeaves[l] = std::move(wLeaf);
      }
    }
  });

  interrupt.throwIfStopped();

  AccumulatedField out;
  out.g = openvdb::FloatGrid::create(0.0f);
  out.weight = openvdb::FloatGrid::create(0.0f);
  for (auto* grid : {&out.g, &out.weight}) {
    (*grid)->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
    (*grid)->setGridClass(openvdb::GRID_UNKNOWN);
  }
  out.g->setName("g");
  out.weight->setName("weight");
  for (std::size_t l = 0; l < leafCount; ++l) {
    out.evaluations += evaluations[l];
    if (!gLeaves[l]) continue;
    out.g->tree().addLeaf(gLeaves[l].release());
    out.weight->tree().addLeaf(wLeaves[l].release());
  }
  return out;
}

}  // namespace levelfuse

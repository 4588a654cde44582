// levelfuse: the fit of a surface to its scans.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/recon/DataFit.h>

#include "ZeroSetDistance.h"


#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse {

namespace {

/// The summary of distances; `beyond` (per distance, or none) and `voxel`
/// (0: none) fill the grid's measures.
DataFit summarise(std::vector<double> distance, const std::vector<char>* beyond, double voxel) {
  DataFit fit;
  fit.readings = distance.size();
  if (distance.empty()) return fit;
  double sum = 0.0, sumSq = 0.0;
  std::size_t near = 0, far = 0;
  for (std::size_t i = 0; i < distance.size(); ++i) {
    sum += distance[i];
    sumSq += distance[i] * distance[i];
    near += voxel > 0.0 && distance[i] <= voxel;
    far += beyond && (*beyond)[i] != 0;
  }
  const double n = static_cast<double>(distance.size());
  fit.mean = sum / n;
  fit.rms = std::sqrt(sumSq / n);
  fit.withinVoxel = static_cast<double>(near) / n;
  fit.beyondBand = static_cast<double>(far) / n;
  std::sort(distance.begin(), distance.end());
  const auto quantile = [&](double q) { return distance[std::min(distance.size() - 1, static_cast<std::size_t>(q * n))]; };
  fit.median = quantile(0.5);
  fit.p90 = quantile(0.9);
  fit.p99 = quantile(0.99);
  return fit;
}

/// Calls `visit(pointOf)` for each point a fit of map m at `stride`
/// measures, `pointOf()` making that point: its samples where it was
/// resampled from them (every stride^2-th), else every stride-th valid
/// reading along its rows and columns. A visit that only counts makes no point.
/// Throws std::invalid_argument for a map whose samples were let go.
template <typename Visit>
void forEachFitPoint(const RangeMap& m, int stride, const Visit& visit) {
  if (m.samplesLetGo())
    throw std::invalid_argument("measureDataFit: the points scan '" + m.name() +
                                "' measured were let go (RangeMap::letSamplesGo): its fit cannot be measured");
  const std::size_t sampleStride = static_cast<std::size_t>(stride) * static_cast<std::size_t>(stride);
  if (!m.samples().empty()) {  // the points measured, where the map was resampled from them
    for (std::size_t i = 0; i < m.samples().size(); i += sampleStride) visit([&] { return m.samples()[i]; });
    return;
  }
  for (int v = 0; v < m.height(); v += stride)
    for (int u = 0; u < m.width(); u += stride)
      if (m.valid(u, v)) visit([&] { return m.readingPoint(u, v); });
}

/// The trilinear interpolant of a grid's values at index point x, and its
/// gradient (world units per voxel), from the eight voxels around x.
struct Trilinear {
  double value;
  openvdb::Vec3d gradient;
};

Trilinear trilinearAt(const openvdb::FloatGrid::ConstAccessor& acc, const openvdb::Vec3d& x) {
  const openvdb::Coord lo = openvdb::Coord::floor(x);
  const openvdb::Vec3d f = x - lo.asVec3d();
  double c[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) c[i][j][k] = acc.getValue(lo.offsetBy(i, j, k));
  const auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  // Along z, then y: the values on the four x-y corners' lines and their z slopes.
  double yz[2][2], dz[2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      yz[i][j] = lerp(c[i][j][0], c[i][j][1], f.z());
      dz[i][j] = c[i][j][1] - c[i][j][0];
    }
  const double x0 = lerp(yz[0][0], yz[0][1], f.y()), x1 = lerp(yz[1][0], yz[1][1], f.y());
  Trilinear t;
  t.value = lerp(x0, x1, f.x());
  t.gradient = openvdb::Vec3d(
      x1 - x0, lerp(yz[0][1] - yz[0][0], yz[1][1] - yz[1][0], f.x()),
      lerp(lerp(dz[0][0], dz[0][1], f.y()), lerp(dz[1][0], dz[1][1], f.y()), f.x()));
  return t;
}

}  // namespace

DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const std::vector<RangeMap>& maps, int stride) {
  return measureDataFit(levelSet, rangeMapsOf(maps), stride);
}

DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const RangeMapSequence& maps, int stride) {
  if (stride < 1) throw std::invalid_argument("measureDataFit: the stride must be at least 1");
  requireLevelSet(levelSet, "measureDataFit");
  std::vector<openvdb::Vec3d> points;
  maps([&](const RangeMap& m) { forEachFitPoint(m, stride, [&](const auto& pointOf) { points.push_back(pointOf()); }); });
  return measureDataFit(levelSet, points);
}

int fitStride(const std::vector<RangeMap>& maps, std::size_t atMost) { return fitStride(rangeMapsOf(maps), atMost); }

int fitStride(const RangeMapSequence& maps, std::size_t atMost) {
  if (atMost == 0) throw std::invalid_argument("fitStride: at least one point must be measured");
  // The points each stride measures, counted in one visit of the maps (about
  // 1.6 times their readings: the strides' shares fall as 1 / stride^2).
  std::vector<std::size_t> measured(kLargestFitStride + 1, 0);
  maps([&](const RangeMap& m) {
    for (int stride = 1; stride <= kLargestFitStride; ++stride)
      forEachFitPoint(m, stride, [&](const auto&) { ++measured[static_cast<std::size_t>(stride)]; });
  });
  int stride = 1;
  while (stride < kLargestFitStride && measured[static_cast<std::size_t>(stride)] > atMost) ++stride;
  return stride;
}

DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points) {
  requireLevelSet(levelSet, "measureDataFit");
  if (points.empty()) return DataFit();

  const double background = levelSet.background();
  std::vector<double> distance(points.size());
  std::vector<char> beyond(points.size());
  const double voxel = levelSet.voxelSize()[0];
  // The zero set lies within the band's half-width of any voxel in it: a
  // Newton step longer than that (voxels) comes from a flat spot.
  const double longestStep = 1.0 + background / voxel;
  parallelFor(points.size(), 4096, [&](std::size_t begin, std::size_t end) {
    openvdb::FloatGrid::ConstAccessor acc = levelSet.getConstAccessor();
    for (std::size_t i = begin; i < end; ++i) {
      const openvdb::Vec3d start = levelSet.worldToIndex(points[i]);
      Trilinear psi = trilinearAt(acc, start);
      // Beyond the band where the nearest voxel is not in it.
      beyond[i] = !acc.isValueOn(openvdb::Coord::round(start)) && std::fabs(psi.value) >= 0.999 * background;
      distance[i] = std::fabs(psi.value);
      if (beyond[i]) continue;
      // The values of a narrow band are distances only near the zero set:
      // project the reading onto it along the gradient (Newton's method on
      // the trilinear interpolant) and measure the way it went.
      openvdb::Vec3d x = start;
      for (int step = 0; step < 8 && std::fabs(psi.value) > 1e-4 * voxel; ++step) {
        const double lengthSq = psi.gradient.lengthSqr();
        if (!(lengthSq > 0.0)) break;
        const openvdb::Vec3d move = psi.gradient * (psi.value / lengthSq);  // index space: the gradient is world units per voxel
        if (!(move.length() <= longestStep)) break;  // a flat spot: the step would leave the band
        x -= move;
        psi = trilinearAt(acc, x);
      }
      if (std::fabs(psi.value) <= 1e-3 * voxel) distance[i] = (x - start).length() * voxel;
    }
  });
  // Readings beyond the band: the distance to the zero set's mesh, made
  // only around them.
  std::vector<openvdb::Vec3d> farPoints;
  std::vector<std::size_t> farIndices;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (beyond[i]) {
      farPoints.push_back(points[i]);
      farIndices.push_back(i);
    }
  const std::vector<double> farDistances = detail::distancesToZeroSet(levelSet, farPoints);
  for (std::size_t k = 0; k < farIndices.size(); ++k)
    if (std::isfinite(farDistances[k]))
      distance[farIndices[k]] = std::max(distance[farIndices[k]], farDistances[k]);
  return summarise(std::move(distance), &beyond, voxel);
}

DataFit measureDataFit(const TriangleMesh& mesh, const std::vector<openvdb::Vec3d>& points) {
  if (mesh.triangleCount() == 0) throw std::invalid_argument("measureDataFit: the mesh has no triangles");
  if (points.empty()) return DataFit();
  const NearestTriangle nearest(mesh.xyz, mesh.triangles);
  std::vector<double> distance(points.size());
  parallelFor(points.size(), 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) distance[i] = nearest.distance(points[i]);
  });
  return summariseDistances(std::move(distance));
}

DataFit summariseDistances(std::vector<double> distances) { return summarise(std::move(distances), nullptr, 0.0); }

}  // namespace levelfuse

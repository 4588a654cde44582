// levelfuse: how well a surface fits the scans it was made from.
#pragma once

#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <vector>

namespace levelfuse {

/// Distances from the scans' points to the zero set of a level set (world
/// units): each reading is projected onto the zero set of the trilinear
/// interpolant along its gradient (the band's values are distances only near
/// the zero set) and the distance it went is measured. Readings beyond the
/// narrow band are measured to the nearest triangle of the zero set's mesh
/// (made only around them) and counted in `beyondBand`: a hole in the surface where the scans saw it shows
/// there.
struct DataFit {
  std::size_t readings = 0;   ///< points measured
  double mean = 0.0, rms = 0.0, median = 0.0, p90 = 0.0, p99 = 0.0;
  double withinVoxel = 0.0;   ///< fraction of readings within one voxel of the surface
  double beyondBand = 0.0;    ///< fraction of readings beyond the narrow band
};

/// Measures the fit of `levelSet` to the points the scans measured: each map's
/// samples where it was resampled from them (RangeMap::samples), else its
/// readings; every `stride`-th reading in each direction of each map (every
/// stride^2-th sample). Throws std::invalid_argument, naming it, for a map
/// whose samples were let go (RangeMap::letSamplesGo), as fitStride does.
DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const std::vector<RangeMap>& maps, int stride = 1);
/// The same, of maps visited one at a time (e.g. a Fusion's, unpacked).
DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const RangeMapSequence& maps, int stride = 1);
/// The points a summary of the fit measures at most: a sample of two million
/// gives its mean and quantiles to well under a percent.
inline constexpr std::size_t kFitPointsAtMost = 2'000'000;

/// The smallest stride for measureDataFit(levelSet, maps, stride) that
/// measures at most `atMost` points (at least 1): the fit of a few laser scans
/// takes every point, that of hundreds of depth frames a sample of them.
int fitStride(const std::vector<RangeMap>& maps, std::size_t atMost);
/// The same, of maps visited one at a time (once), up to a stride of kLargestFitStride.
int fitStride(const RangeMapSequence& maps, std::size_t atMost);
/// The largest stride fitStride gives: one reading in 64 along each row and column.
inline constexpr int kLargestFitStride = 64;
/// The same for any points (world units), e.g. a scan's original samples.
DataFit measureDataFit(const openvdb::FloatGrid& levelSet, const std::vector<openvdb::Vec3d>& points);
/// Exact distances from `points` to the triangles of a mesh (world units),
/// whichever tool made it: the same summary, so that a levelfuse surface and
/// another method's mesh are held to one ruler. A mesh has no voxel and no
/// band: `withinVoxel` and `beyondBand` stay 0. Throws std::invalid_argument
/// for a mesh without triangles.
DataFit measureDataFit(const TriangleMesh& mesh, const std::vector<openvdb::Vec3d>& points);

/// The summary of any distances (world units): count, mean, rms, median, p90
/// and p99; `withinVoxel` and `beyondBand` stay 0.
DataFit summariseDistances(std::vector<double> distances);

}  // namespace levelfuse

// levelfuse: a scanner's points binned into the pixels of a spherical grid,
// and what every binning does with them (private to the spherical scans).
#pragma once

#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/math/Mat4.h>

#include <string>
#include <vector>

namespace levelfuse::detail {

/// The grid and readings of a scanner's points binned into pixels.
struct BinnedScan {
  int width = 0, height = 0;
  SphericalProjection grid;
  std::vector<float> ranges;
  std::vector<Rgb8> colours;  ///< of the nearest point of each pixel, if the points have colours
  /// Where each pixel's point lies from the pixel's centre, in pixels (each
  /// within half a pixel, or within one where firings crowd a column): its
  /// column and row offsets.
  std::vector<float> columnOffsets, rowOffsets;
  bool closedTurn = false;  ///< the last column repeats the first
};

/// Moves each reading from its point's direction to its pixel's centre along
/// the surface the neighbouring readings show (their limited slopes): a
/// point off its pixel's centre would otherwise be read as lying on the
/// centre's ray, displaced sideways by up to the distance between rays, which
/// on a surface seen at an angle is a displacement along its normal. A
/// reading without a neighbour on either side of a direction is not moved
/// along it. (The last column of a closed turn, a copy of the first, is
/// filled after: closeTheTurn.)
void centreReadingsOnPixels(BinnedScan& scan);

/// Copies the first column after the last where the turn is closed: no seam.
void closeTheTurn(BinnedScan& scan);

/// The range map of a binned scan, with its colours if it has them.
RangeMap mapOfBinnedScan(BinnedScan scan, const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name);
RangeMap mapOfBinnedScan(BinnedScan scan, const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                         std::string name);

}  // namespace levelfuse::detail

// levelfuse: a spinning LiDAR's sweep as range maps, one per block of lasers
// that share an apex (sweepRangeMaps; see LaserSweep.h).

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/LaserSweep.h>
#include <levelfuse/scan/SphericalScan.h>

#include "BinnedScan.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

/// A block of lasers seen from one apex.
struct LaserBlock {
  std::vector<int> lasers;  ///< by elevation seen from the apex, lowest first (a row each)
  double apexHeight = 0.0;
};

/// The lasers grouped by apex: sorted by apex height and cut where
/// neighbours lie kSharedApex or more apart; a block of one joins the
/// neighbouring block whose apex is nearer.
std::vector<std::vector<int>> lasersByApex(const std::vector<LaserCone>& cones) {
  std::vector<int> byHeight(cones.size());
  std::iota(byHeight.begin(), byHeight.end(), 0);
  std::stable_sort(byHeight.begin(), byHeight.end(),
                   [&](int a, int b) { return cones[std::size_t(a)].apexHeight < cones[std::size_t(b)].apexHeight; });
  std::vector<std::vector<int>> blocks;
  for (std::size_t i = 0; i < byHeight.size(); ++i) {
    const bool apart = i == 0 || cones[std::size_t(byHeight[i])].apexHeight -
                                         cones[std::size_t(byHeight[i - 1])].apexHeight >= kSharedApex;
    if (apart) blocks.emplace_back();
    blocks.back().push_back(byHeight[i]);
  }
  const auto height = [&](const std::vector<int>& block, bool last) {
    return cones[std::size_t(last ? block.back() : block.front())].apexHeight;
  };
  for (std::size_t b = 0; b < blocks.size() && blocks.size() > 1;) {
    if (blocks[b].size() > 1) {
      ++b;
      continue;
    }
    const double own = height(blocks[b], false);
    const bool joinsBelow =
        b + 1 == blocks.size() || (b > 0 && own - height(blocks[b - 1], true) <= height(blocks[b + 1], false) - own);
    std::vector<int>& into = blocks[joinsBelow ? b - 1 : b + 1];
    into.push_back(blocks[b].front());
    blocks.erase(blocks.begin() + static_cast<std::ptrdiff_t>(b));
    b = 0;
  }
  return blocks;
}

/// The elevation of a point seen from an apex at `apexHeight` on the z axis.
double elevationFrom(const Vec3d& p, double apexHeight) {
  return std::atan2(p.z() - apexHeight, std::hypot(p.x(), p.y()));
}

/// Each laser's elevation seen from the block's apex: the median of its points'.
std::vector<double> elevationsFrom(const std::vector<Vec3d>& points, const LaserRows& rows,
                                   const std::vector<int>& lasers, double apexHeight) {
  std::vector<std::vector<double>> seen(rows.lasers.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int laser = rows.laserOfPoint[i];
    if (laser >= 0) seen[std::size_t(laser)].push_back(elevationFrom(points[i], apexHeight));
  }
  std::vector<double> elevations;
  for (int laser : lasers) elevations.push_back(median(std::move(seen[std::size_t(laser)])));
  return elevations;
}

/// The block's lasers as rows, lowest first, seen from their mean apex.
LaserBlock blockOf(const std::vector<Vec3d>& points, const LaserRows& rows, std::vector<int> lasers,
                   std::vector<double>& rowElevations) {
  LaserBlock block;
  for (int laser : lasers) block.apexHeight += rows.lasers[std::size_t(laser)].apexHeight;
  block.apexHeight /= static_cast<double>(lasers.size());
  const std::vector<double> elevations = elevationsFrom(points, rows, lasers, block.apexHeight);
  std::vector<std::size_t> order(lasers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return elevations[a] < elevations[b]; });
  rowElevations.clear();
  for (std::size_t o : order) {
    block.lasers.push_back(lasers[o]);
    rowElevations.push_back(elevations[o]);
  }
  return block;
}

/// A turn of whole columns of about the firings' step, and where the map's
/// columns begin in it: all of it where every column has a return, else
/// after the widest run of empty columns.
struct ColumnsOfTheTurn {
  long perTurn = 0;
  double step = 0.0;  ///< 2 pi / perTurn
  long first = 0;     ///< the turn's column that is the map's first
  long width = 0;     ///< the map's columns, a repeated first one closing a whole turn included
  bool closed = false;
};

ColumnsOfTheTurn columnsOfTheTurn(const std::vector<std::uint8_t>& filled, double step) {
  ColumnsOfTheTurn turn;
  turn.perTurn = static_cast<long>(filled.size());
  turn.step = step;
  long widest = 0, widestEnd = 0, run = 0;
  for (long k = 0; k < 2 * turn.perTurn; ++k) {  // twice round: a run across column 0 is counted whole
    run = filled[std::size_t(k % turn.perTurn)] ? 0 : run + 1;
    if (run > widest && run <= turn.perTurn) {
      widest = run;
      widestEnd = k % turn.perTurn;
    }
  }
  turn.closed = widest == 0;
  turn.first = turn.closed ? 0 : (widestEnd + 1) % turn.perTurn;
  turn.width = turn.closed ? turn.perTurn + 1 : turn.perTurn - widest;
  return turn;
}

/// Where the block's returns go: the column of each firing along its laser's
/// turn (the next one where the laser's previous firing took it, if that
/// lies within a column), and its fractional column.
struct Placed {
  long column;  ///< in the turn, from the cut
  double position;
};

std::vector<Placed> placeFirings(const std::vector<Vec3d>& points, const LaserRows& rows, double step, long perTurn) {
  std::vector<Placed> placed(points.size(), Placed{-1, 0.0});
  std::vector<long> previous(rows.lasers.size(), std::numeric_limits<long>::min());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int laser = rows.laserOfPoint[i];
    if (laser < 0) continue;
    // The turn from the cut, as the sensor spins.
    double turn = std::copysign(1.0, rows.azimuthStep) * (std::atan2(points[i].y(), points[i].x()) - rows.cut);
    turn -= kTurn * std::floor(turn / kTurn);
    const double position = turn / step - 0.5;  // column k's centre lies (k + 1/2) steps from the cut
    long column = std::lround(position);
    long& last = previous[std::size_t(laser)];
    if (column <= last && static_cast<double>(last + 1) - position <= 1.0) column = last + 1;
    last = column;
    placed[i] = Placed{((column % perTurn) + perTurn) % perTurn, position - static_cast<double>(column)};
  }
  return placed;
}

/// The map of one block: its lasers' returns binned, readings their distances from the apex.
detail::BinnedScan binnedBlock(const std::vector<Vec3d>& points, const LaserRows& rows, const LaserBlock& block,
                               const std::vector<double>& rowElevations, const std::vector<Placed>& placed,
                               const ColumnsOfTheTurn& turn) {
  std::vector<int> rowOfLaser(rows.lasers.size(), -1);
  for (std::size_t r = 0; r < block.lasers.size(); ++r) rowOfLaser[std::size_t(block.lasers[r])] = static_cast<int>(r);
  detail::BinnedScan scan;
  scan.width = static_cast<int>(turn.width);
  scan.height = static_cast<int>(block.lasers.size());
  scan.closedTurn = turn.closed;
  const double sign = std::copysign(1.0, rows.azimuthStep);
  scan.grid.azimuthStep = sign * turn.step;
  scan.grid.azimuthStart = rows.cut + sign * (static_cast<double>(turn.first) + 0.5) * turn.step;
  scan.grid.rowElevations = rowElevations;
  scan.grid.elevationStart = rowElevations.front();
  scan.grid.elevationStep = stepsOnRows(turn.step, rowElevations, "a laser block").elevation;
  const std::size_t pixels = std::size_t(scan.width) * std::size_t(scan.height);
  scan.ranges.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  scan.columnOffsets.assign(pixels, 0.0f);
  scan.rowOffsets.assign(pixels, 0.0f);
  const Vec3d apex(0.0, 0.0, block.apexHeight);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int laser = rows.laserOfPoint[i];
    if (laser < 0 || rowOfLaser[std::size_t(laser)] < 0) continue;
    const long u = (placed[i].column - turn.first + turn.perTurn) % turn.perTurn;
    if (u >= turn.width) continue;
    const int v = rowOfLaser[std::size_t(laser)];
    const std::size_t at = std::size_t(v) * std::size_t(scan.width) + std::size_t(u);
    const auto range = static_cast<float>((points[i] - apex).length());
    if (scan.ranges[at] <= range) continue;  // the nearest return of a pixel
    scan.ranges[at] = range;
    scan.columnOffsets[at] = static_cast<float>(placed[i].position);
    const double off = elevationFrom(points[i], block.apexHeight) - rowElevations[std::size_t(v)];
    const std::size_t toward = off >= 0.0 ? std::min<std::size_t>(std::size_t(v) + 1, rowElevations.size() - 1)
                                          : (v > 0 ? std::size_t(v) - 1 : 0);
    const double spacing = std::fabs(rowElevations[toward] - rowElevations[std::size_t(v)]);
    scan.rowOffsets[at] = spacing > 0.0 ? static_cast<float>(std::clamp(off / spacing, -0.5, 0.5)) : 0.0f;
  }
  detail::centreReadingsOnPixels(scan);
  detail::closeTheTurn(scan);
  return scan;
}

/// Which columns of the turn hold a return of the block's lasers.
std::vector<std::uint8_t> filledColumns(const LaserRows& rows, const LaserBlock& block,
                                        const std::vector<Placed>& placed, long perTurn) {
  std::vector<std::uint8_t> inBlock(rows.lasers.size(), 0);
  for (int laser : block.lasers) inBlock[std::size_t(laser)] = 1;
  std::vector<std::uint8_t> filled(std::size_t(perTurn), 0);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const int laser = rows.laserOfPoint[i];
    if (laser >= 0 && inBlock[std::size_t(laser)]) filled[std::size_t(placed[i].column)] = 1;
  }
  return filled;
}

std::string lasersNamed(const std::string& name, const std::vector<int>& lasers) {
  const auto [lowest, highest] = std::minmax_element(lasers.begin(), lasers.end());
  return name + ", lasers " + std::to_string(*lowest + 1) + "-" + std::to_string(*highest + 1);
}

}  // namespace

std::vector<RangeMap> sweepRangeMaps(const std::vector<Vec3d>& points, const LaserRows& rows,
                                     const openvdb::math::Mat4d& sensorToWorld, double sigma,
                                     const std::string& name) {
  if (rows.laserOfPoint.size() != points.size())
    throw std::invalid_argument("sweepRangeMaps: " + std::to_string(rows.laserOfPoint.size()) + " lasers for " +
                                std::to_string(points.size()) + " points");
  if (rows.lasers.size() < 2 || !(std::fabs(rows.azimuthStep) > 0.0))
    throw std::invalid_argument("sweepRangeMaps: a sweep needs two lasers or more and a step between firings");
  const long perTurn = std::max(2L, std::lround(kTurn / std::fabs(rows.azimuthStep)));
  const double step = kTurn / static_cast<double>(perTurn);
  const std::vector<Placed> placed = placeFirings(points, rows, step, perTurn);
  std::vector<RangeMap> maps;
  for (std::vector<int>& lasers : lasersByApex(rows.lasers)) {
    std::vector<double> rowElevations;
    const LaserBlock block = blockOf(points, rows, lasers, rowElevations);
    requireRowElevations(rowElevations, lasersNamed(name, lasers) + " (their elevations)");
    const ColumnsOfTheTurn turn = columnsOfTheTurn(filledColumns(rows, block, placed, perTurn), step);
    openvdb::math::Mat4d apexToSensor = openvdb::math::Mat4d::identity();
    apexToSensor.setTranslation(Vec3d(0.0, 0.0, block.apexHeight));
    maps.push_back(detail::mapOfBinnedScan(binnedBlock(points, rows, block, rowElevations, placed, turn),
                                           apexToSensor * sensorToWorld, sigma, lasersNamed(name, lasers)));
  }
  return maps;
}

}  // namespace levelfuse

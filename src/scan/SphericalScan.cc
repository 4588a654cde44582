// levelfuse: spherical range maps from a scanner's points.

#include <levelfuse/scan/SphericalScan.h>

#include <levelfuse/core/Median.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Vec3d;
constexpr double kTurn = 2.0 * M_PI;

/// A point with a return: finite and not at the scanner.
bool hasReturn(const Vec3d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) && p.lengthSqr() > 0.0;
}

double azimuthOf(const Vec3d& p) { return std::atan2(p.y(), p.x()); }
double elevationOf(const Vec3d& p) { return std::atan2(p.z(), std::hypot(p.x(), p.y())); }

/// A point's direction as the binning sees it.
struct Direction {
  double azimuth, elevation;
  float range;
};

/// Where a grid of `step` puts the angles' pixel centres so that the angles
/// lie nearest them: the circular mean of their phases within a step.
double phaseOf(const std::vector<Direction>& directions, double Direction::*angle, double step) {
  double s = 0.0, c = 0.0;
  for (const Direction& d : directions) {
    const double phase = kTurn * (d.*angle) / step;
    s += std::sin(phase);
    c += std::cos(phase);
  }
  return std::atan2(s, c) / kTurn * step;
}

/// The columns a sweep fills out of the `columns` of a turn: the first after
/// the longest run of empty ones, and how many up to the last filled one.
struct Sweep {
  long first = 0, count = 0;
  bool closed = false;  ///< every column of a whole turn is filled
};

Sweep sweepOf(const std::vector<std::uint8_t>& filled, bool wholeTurn) {
  const long columns = static_cast<long>(filled.size());
  long longestRun = 0, runEnd = 0, run = 0;
  // Twice round, so that a run of empty columns across column 0 is counted whole.
  for (long k = 0; k < 2 * columns; ++k) {
    run = filled[static_cast<std::size_t>(k % columns)] ? 0 : run + 1;
    if (run > longestRun && run <= columns) {
      longestRun = run;
      runEnd = k % columns;
    }
  }
  Sweep sweep;
  if (longestRun == 0) {
    sweep.count = columns;
    sweep.closed = wholeTurn;
    return sweep;
  }
  sweep.first = (runEnd + 1) % columns;
  sweep.count = columns - longestRun;
  return sweep;
}

/// The points' directions, those that can be binned (kPoleMargin).
std::vector<Direction> directionsOf(const std::vector<Vec3d>& points) {
  std::vector<Direction> directions;
  directions.reserve(points.size());
  for (const Vec3d& p : points) {
    if (!hasReturn(p)) continue;
    const double elevation = elevationOf(p);
    if (std::fabs(elevation) > 0.5 * M_PI - kPoleMargin) continue;
    directions.push_back({azimuthOf(p), elevation, static_cast<float>(p.length())});
  }
  return directions;
}

/// The grid and readings of the binned points (sphericalMapFromPoints).
struct BinnedScan {
  int width = 0, height = 0;
  SphericalProjection grid;
  std::vector<float> ranges;
};

BinnedScan binnedScan(const std::vector<Vec3d>& points, AngularSteps steps, const std::string& name) {
  const std::string who = "spherical scan '" + name + "'";
  if (!(steps.azimuth > 0.0) || !(steps.elevation > 0.0) || !std::isfinite(steps.azimuth) ||
      !std::isfinite(steps.elevation) || steps.azimuth > M_PI || steps.elevation > M_PI)
    throw std::invalid_argument(who + ": the angular steps must be positive and less than half a turn");
  const std::vector<Direction> directions = directionsOf(points);
  if (directions.empty()) throw std::invalid_argument(who + ": no point away from the scanner and its poles");
  // A scanner turns a whole number of columns: a step within a twentieth of
  // one of that is taken to be it, so that a whole turn closes.
  const double perTurn = kTurn / steps.azimuth;
  const double wholeColumns = std::round(perTurn);
  const bool wholeTurn = std::fabs(perTurn - wholeColumns) < 0.05;
  if (wholeTurn) steps.azimuth = kTurn / wholeColumns;
  const long columns = static_cast<long>(std::ceil(kTurn / steps.azimuth - 1e-9));

  const double azimuthPhase = phaseOf(directions, &Direction::azimuth, steps.azimuth);
  const double elevationPhase = phaseOf(directions, &Direction::elevation, steps.elevation);
  const auto columnOf = [&](const Direction& d) {
    const long k = std::lround((d.azimuth - azimuthPhase) / steps.azimuth);
    return ((k % columns) + columns) % columns;
  };
  const auto rowOf = [&](const Direction& d) { return std::lround((d.elevation - elevationPhase) / steps.elevation); };

  std::vector<std::uint8_t> filled(static_cast<std::size_t>(columns), 0);
  long lowestRow = std::numeric_limits<long>::max(), highestRow = std::numeric_limits<long>::min();
  for (const Direction& d : directions) {
    filled[static_cast<std::size_t>(columnOf(d))] = 1;
    lowestRow = std::min(lowestRow, rowOf(d));
    highestRow = std::max(highestRow, rowOf(d));
  }
  const Sweep sweep = sweepOf(filled, wholeTurn);

  BinnedScan scan;
  const long width = sweep.count + (sweep.closed ? 1 : 0), height = highestRow - lowestRow + 1;
  if (width < 2 || height < 2)
    throw std::invalid_argument(who + ": its points span " + std::to_string(width) + " column(s) and " +
                                std::to_string(height) +
                                " row(s) of the angular grid; a range map needs at least 2 of each (are the "
                                "angular steps the scanner's?)");
  if (static_cast<double>(width) * static_cast<double>(height) > 2147483647.0)
    throw std::invalid_argument(who + ": an angular grid of " + std::to_string(width) + " x " +
                                std::to_string(height) + " pixels is too large (are the angular steps the scanner's?)");
  scan.width = static_cast<int>(width);
  scan.height = static_cast<int>(height);
  scan.grid.azimuthStart = azimuthPhase + static_cast<double>(sweep.first) * steps.azimuth;
  scan.grid.azimuthStep = steps.azimuth;
  scan.grid.elevationStart = elevationPhase + static_cast<double>(lowestRow) * steps.elevation;
  scan.grid.elevationStep = steps.elevation;
  scan.ranges.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
                     std::numeric_limits<float>::quiet_NaN());
  for (const Direction& d : directions) {
    const long u = ((columnOf(d) - sweep.first) % columns + columns) % columns;
    const long v = rowOf(d) - lowestRow;
    float& reading = scan.ranges[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                                 static_cast<std::size_t>(u)];
    if (!(reading <= d.range)) reading = d.range;  // the nearest point of a pixel
  }
  if (sweep.closed)  // the first column again after the last: no seam
    for (long v = 0; v < height; ++v) {
      const std::size_t row = static_cast<std::size_t>(v) * static_cast<std::size_t>(width);
      scan.ranges[row + static_cast<std::size_t>(width - 1)] = scan.ranges[row];
    }
  return scan;
}

}  // namespace

RangeMap sphericalMapFromPoints(const std::vector<Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name) {
  BinnedScan scan = binnedScan(scannerPoints, steps, name);
  return RangeMap::spherical(scan.width, scan.height, std::move(scan.ranges), scan.grid, scannerToWorld, sigma,
                             std::move(name));
}

RangeMap sphericalMapFromPoints(const std::vector<Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                                std::string name) {
  BinnedScan scan = binnedScan(scannerPoints, steps, name);
  return RangeMap::spherical(scan.width, scan.height, std::move(scan.ranges), scan.grid, scannerToWorld, noise,
                             std::move(name));
}

AngularSteps stepsOfGrid(const std::vector<Vec3d>& scannerPoints, int columns, int rows) {
  if (columns < 1 || rows < 1 ||
      scannerPoints.size() != static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows))
    throw std::invalid_argument("stepsOfGrid: " + std::to_string(scannerPoints.size()) + " points for " +
                                std::to_string(columns) + " columns of " + std::to_string(rows) + " rows");
  const auto at = [&](int c, int r) -> const Vec3d& {
    return scannerPoints[static_cast<std::size_t>(c) * static_cast<std::size_t>(rows) + static_cast<std::size_t>(r)];
  };
  // At most about a million neighbours along each direction: the median of a
  // sample, evenly spread, is the scanner's step.
  const std::size_t stride = std::max<std::size_t>(1, scannerPoints.size() / 1000000);
  std::vector<double> alongColumns, alongRows;
  for (std::size_t i = 0; i < scannerPoints.size(); i += stride) {
    const int c = static_cast<int>(i / static_cast<std::size_t>(rows)), r = static_cast<int>(i % rows);
    const Vec3d& p = at(c, r);
    if (!hasReturn(p)) continue;
    if (r + 1 < rows && hasReturn(at(c, r + 1)))
      alongColumns.push_back(std::fabs(elevationOf(at(c, r + 1)) - elevationOf(p)));
    if (c + 1 < columns && hasReturn(at(c + 1, r))) {
      double turn = std::fabs(azimuthOf(at(c + 1, r)) - azimuthOf(p));
      alongRows.push_back(std::min(turn, kTurn - turn));
    }
  }
  if (alongColumns.empty() || alongRows.empty())
    throw std::invalid_argument(std::string("stepsOfGrid: no two neighbouring points along a ") +
                                (alongColumns.empty() ? "column" : "row") + " both have returns");
  AngularSteps steps{median(std::move(alongRows)), median(std::move(alongColumns))};
  if (!(steps.azimuth > 0.0) || !(steps.elevation > 0.0))
    throw std::invalid_argument("stepsOfGrid: most neighbouring points lie in one direction from the scanner");
  return steps;
}

}  // namespace levelfuse

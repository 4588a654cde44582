// levelfuse: spherical range maps from a scanner's points.

#include <levelfuse/scan/SphericalScan.h>

#include <levelfuse/core/Median.h>

#include "BinnedScan.h"
#include "PointDirection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

using detail::azimuthOf;
using detail::elevationOf;
using detail::hasReturn;
using detail::BinnedScan;
using detail::centreReadingsOnPixels;
using detail::closeTheTurn;

/// A point's direction as the binning sees it.
struct BinnedPoint {
  double azimuth, elevation;
  float range;
  std::size_t point;  ///< which of the points
};

/// Where a grid of `step` puts the angles' pixel centres so that the angles
/// lie nearest them: the circular mean of their phases within a step.
template <typename AngleOf>
double phaseOf(const std::vector<BinnedPoint>& directions, const AngleOf& angleOf, double step) {
  double s = 0.0, c = 0.0;
  for (const BinnedPoint& d : directions) {
    const double phase = kTurn * angleOf(d) / step;
    s += std::sin(phase);
    c += std::cos(phase);
  }
  return std::atan2(s, c) / kTurn * step;
}

/// An angle's turn from `from`, in [0, 2 pi).
double turnFrom(double angle, double from) {
  const double turn = angle - from;
  return turn - kTurn * std::floor(turn / kTurn);
}

/// Where a turn of azimuths may be cut without cutting the sweep: the
/// middle of the widest run of empty bins of `step` centred on the points'
/// phase, or, with every bin filled, between two of them (`closed` then tells
/// whether the turn is a whole number of steps, to be closed).
struct TurnCut {
  double cut = 0.0;
  bool closed = false;
};

TurnCut turnCutOf(const std::vector<BinnedPoint>& directions, double step, bool wholeTurn) {
  const double phase = phaseOf(directions, [](const BinnedPoint& d) { return d.azimuth; }, step);
  const double firstEdge = phase - 0.5 * step;  // bin 0 is [firstEdge, firstEdge + step)
  const long bins = static_cast<long>(std::ceil(kTurn / step - 1e-9));
  std::vector<std::uint8_t> filled(static_cast<std::size_t>(bins), 0);
  for (const BinnedPoint& d : directions)
    filled[static_cast<std::size_t>(std::min(static_cast<long>(turnFrom(d.azimuth, firstEdge) / step), bins - 1))] = 1;
  long widest = 0, widestEnd = 0, run = 0;
  // Twice round, so that a run of empty bins across the first is counted whole.
  for (long k = 0; k < 2 * bins; ++k) {
    run = filled[static_cast<std::size_t>(k % bins)] ? 0 : run + 1;
    if (run > widest && run <= bins) {
      widest = run;
      widestEnd = k % bins;
    }
  }
  TurnCut turn;
  turn.cut = firstEdge;
  if (widest == 0) {
    turn.closed = wholeTurn;
    return turn;
  }
  // The middle of the run, from the start of its first bin to the end of its last.
  turn.cut = firstEdge + (static_cast<double>(widestEnd + 1) - 0.5 * static_cast<double>(widest)) * step;
  return turn;
}

/// The points' directions, those that can be binned (kPoleMargin).
std::vector<BinnedPoint> directionsOf(const std::vector<Vec3d>& points) {
  std::vector<BinnedPoint> directions;
  directions.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (const std::optional<detail::PointDirection> d = detail::binnableDirection(points[i]))
      directions.push_back({d->azimuth, d->elevation, static_cast<float>(points[i].length()), i});
  return directions;
}

/// Refuses angular steps that are not positive and less than half a turn,
/// and colours that are not one per point.
void checkBinning(const std::vector<Vec3d>& points, const std::vector<Rgb8>& colours, const AngularSteps& steps,
                  const std::string& who) {
  if (!(steps.azimuth > 0.0) || !(steps.elevation > 0.0) || !std::isfinite(steps.azimuth) ||
      !std::isfinite(steps.elevation) || steps.azimuth > M_PI || steps.elevation > M_PI)
    throw std::invalid_argument(who + ": the angular steps must be positive and less than half a turn");
  if (!colours.empty() && colours.size() != points.size())
    throw std::invalid_argument(who + ": " + std::to_string(colours.size()) + " colours for " +
                                std::to_string(points.size()) + " points");
}

/// The whole number nearest to x (halves up).
long nearestWhole(double x) { return static_cast<long>(std::floor(x + 0.5)); }

/// How far a fractional row or column lies from the centre of its pixel.
float offsetFromCentre(double position) {
  return static_cast<float>(position - static_cast<double>(nearestWhole(position)));
}

/// The rows of a sweep's angular grid: evenly spaced on the points' phase, or
/// the uneven rows given (each point in the row nearest its elevation), from
/// the lowest the points fill (the first given) to the highest (the last).
struct SweepRows {
  SweepRows(const std::vector<BinnedPoint>& directions, const AngularSteps& steps, const std::string& who)
      : uneven(!steps.rowElevations.empty()), step(steps.elevation) {
    if (uneven) requireRowElevations(steps.rowElevations, who);
    given.rowElevations = steps.rowElevations;
    phase = uneven ? 0.0 : phaseOf(directions, [](const BinnedPoint& d) { return d.elevation; }, step);
    if (uneven) {  // the rows given, whichever the points fill
      lowest = 0;
      highest = static_cast<long>(steps.rowElevations.size()) - 1;
      return;
    }
    for (const BinnedPoint& d : directions) {
      lowest = std::min(lowest, row(d));
      highest = std::max(highest, row(d));
    }
  }
  /// A point's fractional row (the lowest's counted too), and its row.
  double position(const BinnedPoint& d) const {
    return uneven ? rowOfElevation(given, d.elevation) : (d.elevation - phase) / step;
  }
  long row(const BinnedPoint& d) const { return nearestWhole(position(d)); }

  bool uneven;
  SphericalProjection given;  ///< the uneven rows' elevations
  double step, phase = 0.0;
  long lowest = std::numeric_limits<long>::max(), highest = std::numeric_limits<long>::min();
};

/// The columns of a sweep's angular grid, counted from its first by each
/// point's azimuth from the cut: the turn is cut in the sweep's widest gap, so
/// that a step which does not divide the turn misplaces no column across it;
/// a whole turn every column of which is filled is closed.
struct SweepColumns {
  SweepColumns(const std::vector<BinnedPoint>& directions, double azimuthStep, bool wholeTurn, long columnsPerTurn)
      : turn(turnCutOf(directions, azimuthStep, wholeTurn)), step(azimuthStep), wholeColumns(columnsPerTurn) {
    const double turnPhase = phaseOf(directions, [&](const BinnedPoint& d) { return turnOf(d); }, step);
    double firstTurn = kTurn;
    for (const BinnedPoint& d : directions) firstTurn = std::min(firstTurn, turnOf(d));
    // The first column on the points' phase, at most half a step from the first point.
    start = turnPhase + step * static_cast<double>(nearestWhole((firstTurn - turnPhase) / step));
    for (const BinnedPoint& d : directions) last = std::max(last, column(d));
  }
  /// A point's azimuth from the cut, its fractional column from the first, and its column.
  double turnOf(const BinnedPoint& d) const { return turnFrom(d.azimuth, turn.cut); }
  double position(const BinnedPoint& d) const { return (turnOf(d) - start) / step; }
  long column(const BinnedPoint& d) const {
    const long u = nearestWhole(position(d));
    return turn.closed ? ((u % wholeColumns) + wholeColumns) % wholeColumns : std::max(0L, u);
  }
  /// Columns in the grid: a closed turn's whole number, and the first again.
  long width() const { return turn.closed ? wholeColumns + 1 : last + 1; }

  TurnCut turn;
  double step;
  long wholeColumns;
  double start = 0.0;
  long last = 0;
};

/// A scan of the grid of `rows` and `columns`, with no reading yet; refuses a
/// grid narrower than 2 pixels either way, or too large.
BinnedScan emptyScanOf(const SweepRows& rows, const SweepColumns& columns, const AngularSteps& steps, bool coloured,
                       const std::string& who) {
  BinnedScan scan;
  const long width = columns.width(), height = rows.highest - rows.lowest + 1;
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
  scan.grid.azimuthStart = columns.turn.cut + columns.start;
  scan.grid.azimuthStep = steps.azimuth;
  scan.grid.elevationStart = rows.phase + static_cast<double>(rows.lowest) * steps.elevation;
  scan.grid.elevationStep = steps.elevation;
  scan.grid.rowElevations = steps.rowElevations;  // RangeMap::spherical takes the start and step from them
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  scan.ranges.assign(pixels, std::numeric_limits<float>::quiet_NaN());
  if (coloured) scan.colours.assign(pixels, Rgb8{0, 0, 0});
  scan.columnOffsets.assign(pixels, 0.0f);
  scan.rowOffsets.assign(pixels, 0.0f);
  scan.closedTurn = columns.turn.closed;
  return scan;
}

/// Each point into its pixel of `scan`, the nearest point of a pixel its reading.
void binPoints(const std::vector<BinnedPoint>& directions, const std::vector<Rgb8>& colours, const SweepRows& rows,
               const SweepColumns& columns, BinnedScan& scan) {
  const long width = scan.width, height = scan.height;
  for (const BinnedPoint& d : directions) {
    const long u = columns.column(d);
    const long v = rows.row(d) - rows.lowest;
    if (v < 0 || v >= height) continue;  // beyond the uneven rows given
    const std::size_t at = static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + static_cast<std::size_t>(u);
    if (scan.ranges[at] <= d.range) continue;  // the nearest point of a pixel
    scan.ranges[at] = d.range;
    scan.columnOffsets[at] = offsetFromCentre(columns.position(d));
    scan.rowOffsets[at] = offsetFromCentre(rows.position(d));
    if (!colours.empty()) scan.colours[at] = colours[d.point];
  }
}

BinnedScan binnedScan(const std::vector<Vec3d>& points, const std::vector<Rgb8>& colours, AngularSteps steps,
                      const std::string& name) {
  const std::string who = "spherical scan '" + name + "'";
  checkBinning(points, colours, steps, who);
  const std::vector<BinnedPoint> directions = directionsOf(points);
  if (directions.empty()) throw std::invalid_argument(who + ": no point away from the scanner and its poles");
  // A scanner turns a whole number of columns: a step within a twentieth of
  // one of that is taken to be it, so that a whole turn closes.
  const double perTurn = kTurn / steps.azimuth;
  const long wholeColumns = std::lround(perTurn);
  const bool wholeTurn = std::fabs(perTurn - static_cast<double>(wholeColumns)) < 0.05;
  if (wholeTurn) steps.azimuth = kTurn / static_cast<double>(wholeColumns);
  const SweepRows rows(directions, steps, who);
  const SweepColumns columns(directions, steps.azimuth, wholeTurn, wholeColumns);
  BinnedScan scan = emptyScanOf(rows, columns, steps, !colours.empty(), who);
  binPoints(directions, colours, rows, columns, scan);
  centreReadingsOnPixels(scan);
  closeTheTurn(scan);
  return scan;
}

}  // namespace

AngularSteps stepsOnRows(double azimuthStep, std::vector<double> rowElevations, const std::string& who) {
  requireRowElevations(rowElevations, who);
  double finest = rowElevations[1] - rowElevations[0];
  for (std::size_t r = 2; r < rowElevations.size(); ++r)
    finest = std::min(finest, rowElevations[r] - rowElevations[r - 1]);
  return AngularSteps{azimuthStep, finest, std::move(rowElevations)};
}

RangeMap sphericalMapFromPoints(const std::vector<Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name,
                                const std::vector<Rgb8>& colours) {
  return detail::mapOfBinnedScan(binnedScan(scannerPoints, colours, steps, name), scannerToWorld, sigma,
                                 std::move(name));
}

RangeMap sphericalMapFromPoints(const std::vector<Vec3d>& scannerPoints, const AngularSteps& steps,
                                const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                                std::string name, const std::vector<Rgb8>& colours) {
  return detail::mapOfBinnedScan(binnedScan(scannerPoints, colours, steps, name), scannerToWorld, noise,
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

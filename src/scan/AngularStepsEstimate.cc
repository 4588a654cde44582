// levelfuse: the angular steps of an unordered scan, estimated from its points
// (estimateAngularSteps; see SphericalScan.h).

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/SphericalScan.h>

#include "PointDirection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

/// Elevations sorted to find the rows: a sample of at most this many.
constexpr std::size_t kMaxSampledDirections = 1000000;
/// Rows whose azimuths are gathered to find the azimuth step: at most this many.
constexpr std::size_t kMaxRowsForAzimuths = 32;
/// Angles closer than this (radians) are the same angle written twice.
constexpr double kSameAngle = 1e-9;
/// Elevations come in rows when the gaps between rows are at least this many
/// times the widest gap within one.
constexpr double kRowContrast = 4.0;
/// Row splits tried, the most contrasted first.
constexpr std::size_t kRowSplitsTried = 4;
/// A gap within this fraction of the lower quartile of the gaps is a step.
constexpr double kStepWindow = 0.25;

using detail::binnableDirection;
using Direction = detail::PointDirection;

/// The directions of every k-th point, k chosen so that at most
/// kMaxSampledDirections are taken.
std::vector<Direction> sampledDirections(const std::vector<Vec3d>& points) {
  const std::size_t stride = points.size() / kMaxSampledDirections + 1;
  std::vector<Direction> sample;
  sample.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (const std::optional<Direction> d = binnableDirection(points[i])) sample.push_back(*d);
  return sample;
}

std::size_t countDirections(const std::vector<Vec3d>& points) {
  return static_cast<std::size_t>(
      std::count_if(points.begin(), points.end(), [](const Vec3d& p) { return binnableDirection(p).has_value(); }));
}

/// The typical step of gaps between neighbouring rays: the median of those
/// within kStepWindow of their lower quartile (gaps over missing rays, two
/// steps or more, and repeated angles left out); none without gaps.
std::optional<double> typicalStep(std::vector<double> gaps) {
  gaps.erase(std::remove_if(gaps.begin(), gaps.end(), [](double g) { return !(g > kSameAngle); }), gaps.end());
  if (gaps.empty()) return std::nullopt;
  const double lowerQuartile = quantile(gaps, 0.25);
  std::vector<double> steps;
  for (const double g : gaps)
    if (std::fabs(g - lowerQuartile) <= kStepWindow * lowerQuartile) steps.push_back(g);
  return median(std::move(steps));
}

/// The angle of the widest turn of azimuths without a direction: a turn for
/// directions that all share one azimuth.
double widestAzimuthGap(const std::vector<Direction>& directions) {
  std::vector<double> azimuths;
  azimuths.reserve(directions.size());
  for (const Direction& d : directions) azimuths.push_back(d.azimuth);
  std::sort(azimuths.begin(), azimuths.end());
  double widest = azimuths.front() + kTurn - azimuths.back();
  for (std::size_t i = 1; i < azimuths.size(); ++i) widest = std::max(widest, azimuths[i] - azimuths[i - 1]);
  return widest;
}

void requireDirections(const std::vector<Direction>& sample) {
  if (sample.size() < kMinPointsForSteps)
    throw std::invalid_argument("estimating the angular steps needs at least " + std::to_string(kMinPointsForSteps) +
                                " points away from the scanner and its poles, not " + std::to_string(sample.size()));
  const auto [lowest, highest] = std::minmax_element(
      sample.begin(), sample.end(), [](const Direction& a, const Direction& b) { return a.elevation < b.elevation; });
  if (highest->elevation - lowest->elevation <= kSameAngle && widestAzimuthGap(sample) >= kTurn - kSameAngle)
    throw std::invalid_argument("estimating the angular steps: all the points lie in one direction from the scanner");
}

/// Rows of elevations: their centres, lowest first.
struct Rows {
  std::vector<double> centres;
  std::vector<double> centreGaps() const {
    std::vector<double> gaps;
    for (std::size_t i = 1; i < centres.size(); ++i) gaps.push_back(centres[i] - centres[i - 1]);
    return gaps;
  }
};

/// The sorted elevations cut at every gap wider than `threshold`, if the runs
/// between the cuts are rows: each run much narrower than the gaps between them.
std::optional<Rows> rowsCutAt(const std::vector<double>& sorted, double threshold) {
  Rows rows;
  std::vector<double> extents;
  std::size_t first = 0;
  for (std::size_t i = 1; i <= sorted.size(); ++i) {
    if (i < sorted.size() && sorted[i] - sorted[i - 1] <= threshold) continue;
    rows.centres.push_back(std::accumulate(sorted.begin() + static_cast<std::ptrdiff_t>(first),
                                           sorted.begin() + static_cast<std::ptrdiff_t>(i), 0.0) /
                           static_cast<double>(i - first));
    extents.push_back(sorted[i - 1] - sorted[first]);
    first = i;
  }
  const std::optional<double> step = typicalStep(rows.centreGaps());
  if (rows.centres.size() < 3 || !step || !(quantile(extents, 0.9) <= 0.5 * *step)) return std::nullopt;
  return rows;
}

/// The rows the elevations come in, if they come in rows: the cut between the
/// gaps within rows and those between them is where the sorted gaps fall
/// most steeply (by at least kRowContrast), leaving at least three rows of
/// three elevations on average.
std::optional<Rows> elevationRows(const std::vector<Direction>& sample) {
  std::vector<double> sorted;
  sorted.reserve(sample.size());
  for (const Direction& d : sample) sorted.push_back(d.elevation);
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> gaps;  // widest first, repeated angles as kSameAngle
  for (std::size_t i = 1; i < sorted.size(); ++i) gaps.push_back(std::max(sorted[i] - sorted[i - 1], kSameAngle));
  std::sort(gaps.begin(), gaps.end(), std::greater<>());
  // Cutting the k widest gaps makes k + 1 rows.
  std::vector<std::pair<double, std::size_t>> contrasts;
  for (std::size_t k = 2; k <= sorted.size() / 3 && k < gaps.size(); ++k)
    if (gaps[k - 1] >= kRowContrast * gaps[k]) contrasts.emplace_back(gaps[k - 1] / gaps[k], k);
  std::sort(contrasts.begin(), contrasts.end(), std::greater<>());
  for (std::size_t t = 0; t < std::min(contrasts.size(), kRowSplitsTried); ++t) {
    const std::size_t k = contrasts[t].second;
    if (std::optional<Rows> rows = rowsCutAt(sorted, std::sqrt(gaps[k - 1] * gaps[k]))) return rows;
  }
  return std::nullopt;
}

/// The azimuth step from the gaps between neighbours within rows: the points
/// within a quarter of an elevation step of one of (at most
/// kMaxRowsForAzimuths of) the rows, sorted by azimuth along each.
std::optional<double> azimuthStepWithinRows(const std::vector<Vec3d>& points, const Rows& rows,
                                            double elevationStep) {
  const std::size_t every = (rows.centres.size() + kMaxRowsForAzimuths - 1) / kMaxRowsForAzimuths;
  std::vector<std::vector<double>> azimuths(rows.centres.size());
  for (const Vec3d& p : points) {
    const std::optional<Direction> d = binnableDirection(p);
    if (!d) continue;
    const auto above = std::lower_bound(rows.centres.begin(), rows.centres.end(), d->elevation);
    std::size_t row = static_cast<std::size_t>(above - rows.centres.begin());
    if (row == rows.centres.size() || (row > 0 && d->elevation - rows.centres[row - 1] < *above - d->elevation))
      --row;
    if (row % every == 0 && std::fabs(d->elevation - rows.centres[row]) <= 0.25 * elevationStep)
      azimuths[row].push_back(d->azimuth);
  }
  std::vector<double> gaps;
  for (std::vector<double>& row : azimuths) {
    if (row.size() < 2) continue;
    std::sort(row.begin(), row.end());
    for (std::size_t i = 1; i < row.size(); ++i) gaps.push_back(row[i] - row[i - 1]);
    gaps.push_back(row.front() + kTurn - row.back());  // across azimuth -pi
  }
  return typicalStep(std::move(gaps));
}

/// The mean angular spacing of `count` directions of which `sample` is an
/// even sample: the root of the solid angle they cover per direction. The
/// cover is counted in cells of about four sample spacings, refined twice
/// from cells of a degree.
double meanSpacing(const std::vector<Direction>& sample, std::size_t count) {
  double cell = M_PI / 180.0, solidAngle = 0.0;
  for (int refinement = 0; refinement < 3; ++refinement) {
    const auto columns = static_cast<std::int64_t>(std::ceil(kTurn / cell));
    std::vector<std::int64_t> cells;
    cells.reserve(sample.size());
    for (const Direction& d : sample)
      cells.push_back(static_cast<std::int64_t>(std::floor((d.elevation + 0.5 * M_PI) / cell)) * columns +
                      static_cast<std::int64_t>(std::floor((d.azimuth + M_PI) / cell)));
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    solidAngle = 0.0;
    for (const std::int64_t c : cells) {
      const double elevation = (static_cast<double>(c / columns) + 0.5) * cell - 0.5 * M_PI;
      solidAngle += cell * cell * std::cos(std::clamp(elevation, -0.5 * M_PI, 0.5 * M_PI));
    }
    cell = std::clamp(4.0 * std::sqrt(solidAngle / static_cast<double>(sample.size())), 1e-6, M_PI / 180.0);
  }
  return std::sqrt(solidAngle / static_cast<double>(count));
}

/// The rows' centres if they are unevenly spaced (a gap between neighbouring
/// rows more than kStepWindow of a step from the typical `step`) and at most
/// kMostUnevenRows; else none.
std::vector<double> unevenRowElevations(const Rows& rows, double step) {
  if (rows.centres.size() > kMostUnevenRows) return {};
  for (const double gap : rows.centreGaps())
    if (std::fabs(gap - step) > kStepWindow * step) return rows.centres;
  return {};
}

}  // namespace

AngularSteps estimateAngularSteps(const std::vector<Vec3d>& scannerPoints) {
  const std::vector<Direction> sample = sampledDirections(scannerPoints);
  requireDirections(sample);
  if (const std::optional<Rows> rows = elevationRows(sample)) {
    const double elevationStep = *typicalStep(rows->centreGaps());
    if (const std::optional<double> azimuthStep = azimuthStepWithinRows(scannerPoints, *rows, elevationStep))
      return AngularSteps{*azimuthStep, elevationStep, unevenRowElevations(*rows, elevationStep)};
  }
  const double spacing = meanSpacing(sample, countDirections(scannerPoints));
  return AngularSteps{spacing, spacing, {}};
}

}  // namespace levelfuse

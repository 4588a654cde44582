// levelfuse: the lasers of a spinning LiDAR's sweep listed in firing order,
// and their cones (lasersInFiringOrder; see LaserSweep.h).

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/LaserSweep.h>

#include "PointDirection.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

/// Fewer turns than this are not a sweep listed laser by laser.
constexpr double kFewestTurns = 4.0;
/// A laser with fewer returns than this has no cone that can be trusted.
constexpr std::size_t kFewestLaserReturns = 16;
/// Points on either side of a laser's turn weighed for the other laser.
constexpr std::size_t kCrossingWindow = 16;
/// A firing order turns one way: at most this share of steps go back.
constexpr double kMostStepsBack = 0.05;
/// Points this many times the median misfit off a cone are left out of its
/// second fit (returns of another laser, or of a moving object).
constexpr double kOutlierMisfits = 5.0;
/// Cones must fit their points this well, as a share of the typical spacing
/// between neighbouring lasers (their 90th percentile misfit).
constexpr double kFitOfCones = 0.1;
/// A laser's returns tell its apex when their distances from the axis
/// spread by at least this share of their mean (one laser that saw only the
/// road around the sensor saw it at one distance).
constexpr double kApexSpread = 0.05;
/// Misfits below this (radians) are rounding: a cone fits its points exactly.
constexpr double kSameCone = 1e-7;
/// Turns between consecutive returns of a laser longer than this many steps
/// are not counted in the mean step (how many firings they span is unsure).
constexpr double kMostStepsBetween = 8.0;
/// Runs of firings without a missing return at least this long measure the
/// mean step between firings.
constexpr std::size_t kStepRun = 32;

/// A laser's turn may step back this far between firings (the azimuths of
/// near returns shift with a laser's offset from the axis); any larger turn
/// back is a turn forward past firings without a return.
constexpr double kLargestStepBack = 30.0 * M_PI / 180.0;
/// More turns than this are not a sweep's lasers.
constexpr int kMostLasers = 512;

/// A return in the order it was listed: its index among the points, its
/// azimuth unwrapped along the order, its distance from the z axis and its height.
struct Firing {
  std::size_t point;
  double turned;  ///< azimuth, radians, unwrapped along the order as the sensor spins
  double radial, height;
};

/// +1 if most steps between consecutive returns turn counterclockwise (seen
/// from above), else -1.
double spinOf(const std::vector<Vec3d>& points) {
  long forward = 0;
  std::optional<double> previous;
  for (const Vec3d& p : points) {
    const std::optional<detail::PointDirection> d = detail::binnableDirection(p);
    if (!d) continue;
    if (previous) forward += std::remainder(d->azimuth - *previous, kTurn) >= 0.0 ? 1 : -1;
    previous = d->azimuth;
  }
  return forward >= 0 ? 1.0 : -1.0;
}

/// The returns in order, their azimuths unwrapped as the sensor spins
/// (`spin` times the azimuth, so that the turn grows).
std::vector<Firing> firingsOf(const std::vector<Vec3d>& points, double spin) {
  std::vector<Firing> firings;
  firings.reserve(points.size());
  double previous = 0.0, turned = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::optional<detail::PointDirection> d = detail::binnableDirection(points[i]);
    if (!d) continue;
    const double azimuth = spin * d->azimuth;
    if (!firings.empty()) {
      double step = std::remainder(azimuth - previous, kTurn);
      if (step < -kLargestStepBack) step += kTurn;
      turned += step;
    } else {
      turned = azimuth;
    }
    previous = azimuth;
    firings.push_back({i, turned, std::hypot(points[i].x(), points[i].y()), points[i].z()});
  }
  return firings;
}

/// How far a firing lies off a cone, as an angle seen from its apex (radians).
double misfit(const Firing& f, const LaserCone& cone) {
  return std::atan2(f.height - cone.apexHeight, f.radial) - cone.elevation;
}

/// The cone z = h + r tan(elevation) of least squares through `firings`.
std::optional<LaserCone> leastSquaresCone(const std::vector<const Firing*>& firings) {
  if (firings.size() < kFewestLaserReturns) return std::nullopt;
  double n = 0.0, sr = 0.0, sz = 0.0, srr = 0.0, srz = 0.0;
  for (const Firing* f : firings) {
    n += 1.0;
    sr += f->radial;
    sz += f->height;
    srr += f->radial * f->radial;
    srz += f->radial * f->height;
  }
  const double det = n * srr - sr * sr;
  if (!(det > 1e-12 * n * srr)) return std::nullopt;  // every return at one distance: no apex
  const double slope = (n * srz - sr * sz) / det;
  return LaserCone{(sz - slope * sr) / n, std::atan(slope)};
}

/// True when a laser's returns lie at distances from the axis spread
/// enough (kApexSpread) to tell the height of its apex from its elevation.
bool spreadEnoughForAnApex(const std::vector<const Firing*>& firings) {
  double sum = 0.0, sumSq = 0.0;
  for (const Firing* f : firings) {
    sum += f->radial;
    sumSq += f->radial * f->radial;
  }
  const double n = static_cast<double>(firings.size()), mean = sum / n;
  return std::sqrt(std::max(0.0, sumSq / n - mean * mean)) >= kApexSpread * mean;
}

/// The laser's cone, fitted twice: the second time without the points far
/// off the first. None for too few returns or too little spread.
std::optional<LaserCone> fittedCone(const std::vector<const Firing*>& firings) {
  if (firings.size() < kFewestLaserReturns || !spreadEnoughForAnApex(firings)) return std::nullopt;
  const std::optional<LaserCone> first = leastSquaresCone(firings);
  if (!first) return std::nullopt;
  std::vector<double> misfits;
  misfits.reserve(firings.size());
  for (const Firing* f : firings) misfits.push_back(std::fabs(misfit(*f, *first)));
  const double limit = std::max(kOutlierMisfits * median(misfits), kSameCone);
  std::vector<const Firing*> kept;
  for (const Firing* f : firings)
    if (std::fabs(misfit(*f, *first)) <= limit) kept.push_back(f);
  return leastSquaresCone(kept);
}

/// The elevation of a laser whose apex is known: the median of its returns' seen from it.
double elevationFromApex(const std::vector<const Firing*>& firings, double apexHeight) {
  std::vector<double> elevations;
  elevations.reserve(firings.size());
  for (const Firing* f : firings) elevations.push_back(std::atan2(f->height - apexHeight, f->radial));
  return median(std::move(elevations));
}

/// The median turn between consecutive firings that went forward.
double medianForwardStep(const std::vector<Firing>& firings) {
  std::vector<double> steps;
  for (std::size_t k = 1; k < firings.size(); ++k)
    if (firings[k].turned > firings[k - 1].turned) steps.push_back(firings[k].turned - firings[k - 1].turned);
  return steps.empty() ? 0.0 : median(std::move(steps));
}

/// A first estimate of the mean step between firings of one laser: over
/// runs of at least kStepRun firings without a missing return (no step
/// beyond 1.5 typical ones), else over every such step.
double stepOverRuns(const std::vector<Firing>& firings, const std::vector<int>& laserOf, double typical) {
  double runTurn = 0.0, allTurn = 0.0;
  std::size_t runSteps = 0, allSteps = 0, run = 0;
  double turn = 0.0;
  const auto endRun = [&] {
    if (run >= kStepRun) {
      runTurn += turn;
      runSteps += run;
    }
    run = 0;
    turn = 0.0;
  };
  for (std::size_t k = 1; k < firings.size(); ++k) {
    const double step = firings[k].turned - firings[k - 1].turned;
    if (laserOf[k] != laserOf[k - 1] || !(step > 0.0 && step < 1.5 * typical)) {
      endRun();
      continue;
    }
    turn += step;
    ++run;
    allTurn += step;
    ++allSteps;
  }
  endRun();
  if (runSteps > 0) return runTurn / static_cast<double>(runSteps);
  return allSteps > 0 ? allTurn / static_cast<double>(allSteps) : typical;
}

/// The mean step between firings of one laser: every turn between
/// consecutive returns of a laser (up to kMostStepsBetween steps) over the
/// firings it spans, each counted as the nearest whole number of steps of
/// the first estimate (stepOverRuns), at least one, so that the returns
/// missing from a run count as the firings they were.
double meanFiringStep(const std::vector<Firing>& firings, const std::vector<int>& laserOf, double typical) {
  const double first = stepOverRuns(firings, laserOf, typical);
  double turned = 0.0, fired = 0.0;
  for (std::size_t k = 1; k < firings.size(); ++k) {
    const double step = firings[k].turned - firings[k - 1].turned;
    if (laserOf[k] != laserOf[k - 1] || !(step > 0.0 && step < kMostStepsBetween * first)) continue;
    turned += step;
    fired += std::max(1.0, std::round(step / first));
  }
  return fired > 0.0 ? turned / fired : first;
}

/// Each firing's turn from the first cut (laser 0 first): where the order
/// crosses the azimuth half a typical step before its first firing.
std::vector<int> turnsFromTheCut(const std::vector<Firing>& firings, double cut) {
  std::vector<int> turn(firings.size());
  for (std::size_t k = 0; k < firings.size(); ++k)
    turn[k] = std::max(0, static_cast<int>(std::floor((firings[k].turned - cut) / kTurn)));
  return turn;
}

/// The firings of each laser.
std::vector<std::vector<const Firing*>> firingsByLaser(const std::vector<Firing>& firings,
                                                       const std::vector<int>& laserOf, int lasers) {
  std::vector<std::vector<const Firing*>> by(static_cast<std::size_t>(lasers));
  for (std::size_t k = 0; k < firings.size(); ++k) by[static_cast<std::size_t>(laserOf[k])].push_back(&firings[k]);
  return by;
}

/// Each laser's cone: fitted where its returns tell its apex, else with
/// the apex of the nearest laser in firing order whose returns do (the
/// earlier one of two as near; the axis's origin if none does) and the
/// elevation seen from there. None for a laser with too few returns.
std::vector<std::optional<LaserCone>> conesOf(const std::vector<Firing>& firings, const std::vector<int>& laserOf,
                                              int lasers) {
  const std::vector<std::vector<const Firing*>> by = firingsByLaser(firings, laserOf, lasers);
  std::vector<std::optional<LaserCone>> fitted, cones(by.size());
  for (const auto& own : by) fitted.push_back(fittedCone(own));
  for (std::size_t l = 0; l < by.size(); ++l) {
    if (fitted[l]) {
      cones[l] = fitted[l];
      continue;
    }
    if (by[l].size() < kFewestLaserReturns) continue;
    double apexHeight = 0.0;
    for (std::size_t distance = 1; distance < by.size(); ++distance) {
      if (l >= distance && fitted[l - distance]) {
        apexHeight = fitted[l - distance]->apexHeight;
        break;
      }
      if (l + distance < by.size() && fitted[l + distance]) {
        apexHeight = fitted[l + distance]->apexHeight;
        break;
      }
    }
    cones[l] = LaserCone{apexHeight, elevationFromApex(by[l], apexHeight)};
  }
  return cones;
}

/// Where the order passes from one laser's turn to the next's.
std::vector<std::size_t> turnsBegin(const std::vector<int>& laserOf) {
  std::vector<std::size_t> begins;
  for (std::size_t k = 1; k < laserOf.size(); ++k)
    if (laserOf[k] != laserOf[k - 1]) begins.push_back(k);
  return begins;
}

/// Moves the turn between each laser and the next to where the
/// kCrossingWindow points on either side fit their cones best (a sweep's
/// lasers need not begin their turns at quite the same azimuth).
void splitTurnsWhereTheConesFit(const std::vector<Firing>& firings, std::vector<int>& laserOf,
                                const std::vector<std::optional<LaserCone>>& cones) {
  const std::vector<std::size_t> begins = turnsBegin(laserOf);
  for (std::size_t t = 0; t < begins.size(); ++t) {
    const std::size_t k = begins[t];
    const int before = laserOf[k - 1], after = laserOf[k];
    const auto& coneBefore = cones[static_cast<std::size_t>(before)];
    const auto& coneAfter = cones[static_cast<std::size_t>(after)];
    if (!coneBefore || !coneAfter) continue;
    // Within the two lasers' turns.
    const std::size_t begin = std::max(t > 0 ? begins[t - 1] : 0, k >= kCrossingWindow ? k - kCrossingWindow : 0);
    const std::size_t end = std::min(t + 1 < begins.size() ? begins[t + 1] : firings.size(), k + kCrossingWindow);
    std::size_t bestSplit = k;
    double bestMisfit = std::numeric_limits<double>::infinity();
    for (std::size_t split = begin; split <= end; ++split) {
      double sum = 0.0;
      for (std::size_t j = begin; j < end; ++j) {
        const double m = misfit(firings[j], j < split ? *coneBefore : *coneAfter);
        sum += m * m;
      }
      if (sum < bestMisfit) {
        bestMisfit = sum;
        bestSplit = split;
      }
    }
    for (std::size_t j = begin; j < end; ++j) laserOf[j] = j < bestSplit ? before : after;
  }
}

/// True when the cones fit their lasers' points within kFitOfCones of the
/// typical spacing between neighbouring lasers.
bool conesFit(const std::vector<Firing>& firings, const std::vector<int>& laserOf,
              const std::vector<std::optional<LaserCone>>& cones) {
  std::vector<double> elevations, misfits;
  for (const auto& cone : cones)
    if (cone) elevations.push_back(cone->elevation);
  if (elevations.size() < 2) return false;
  std::sort(elevations.begin(), elevations.end());
  std::vector<double> spacings;
  for (std::size_t i = 1; i < elevations.size(); ++i) spacings.push_back(elevations[i] - elevations[i - 1]);
  const double spacing = median(std::move(spacings));
  for (std::size_t k = 0; k < firings.size(); ++k)
    if (const auto& cone = cones[static_cast<std::size_t>(laserOf[k])])
      misfits.push_back(std::fabs(misfit(firings[k], *cone)));
  return quantile(std::move(misfits), 0.9) <= kFitOfCones * spacing;
}

/// True when the order turns one way: few steps back, and at least kFewestTurns turns.
bool turnsOneWay(const std::vector<Firing>& firings) {
  if (firings.size() < 2) return false;
  std::size_t back = 0;
  for (std::size_t k = 1; k < firings.size(); ++k) back += firings[k].turned < firings[k - 1].turned;
  const double turns = (firings.back().turned - firings.front().turned) / kTurn;
  return static_cast<double>(back) <= kMostStepsBack * static_cast<double>(firings.size()) &&
         turns >= kFewestTurns - 1.0 && turns < kMostLasers;
}

}  // namespace

std::optional<LaserRows> lasersInFiringOrder(const std::vector<Vec3d>& points) {
  // A sensor that spins clockwise lists its azimuths falling: its turns are counted the other way.
  const double spin = spinOf(points);
  const std::vector<Firing> firings = firingsOf(points, spin);
  if (!turnsOneWay(firings)) return std::nullopt;
  const double typical = medianForwardStep(firings);
  if (!(typical > 0.0)) return std::nullopt;

  const double cut = firings.front().turned - 0.5 * typical;
  std::vector<int> laserOf = turnsFromTheCut(firings, cut);
  const int lasers = *std::max_element(laserOf.begin(), laserOf.end()) + 1;  // a step back may end the order
  std::vector<std::optional<LaserCone>> cones = conesOf(firings, laserOf, lasers);
  splitTurnsWhereTheConesFit(firings, laserOf, cones);
  cones = conesOf(firings, laserOf, lasers);
  if (!conesFit(firings, laserOf, cones)) return std::nullopt;

  LaserRows rows;
  rows.cut = spin * cut;
  rows.azimuthStep = spin * meanFiringStep(firings, laserOf, typical);
  // The lasers with a cone, numbered in the order they fired.
  std::vector<int> numbered(cones.size(), -1);
  for (std::size_t l = 0; l < cones.size(); ++l)
    if (cones[l]) {
      numbered[l] = static_cast<int>(rows.lasers.size());
      rows.lasers.push_back(*cones[l]);
    }
  rows.laserOfPoint.assign(points.size(), -1);
  for (std::size_t k = 0; k < firings.size(); ++k)
    rows.laserOfPoint[firings[k].point] = numbered[static_cast<std::size_t>(laserOf[k])];
  return rows;
}

}  // namespace levelfuse

// levelfuse: exact sums of a step's tallies.

#include <levelfuse/levelset/StepTally.h>

#include <algorithm>
#include <cmath>

namespace levelfuse {

namespace {

/// Adds (high, low) to the 128-bit number (sumHigh, sumLow).
void add128(std::uint64_t& sumHigh, std::uint64_t& sumLow, std::uint64_t high, std::uint64_t low) {
  const std::uint64_t before = sumLow;
  sumLow += low;
  sumHigh += high + (sumLow < before ? 1u : 0u);
}

}  // namespace

void StepTally::addSquaredChanges(double voxelsSquared) {
  if (!(voxelsSquared > 0.0)) return;
  const double units = std::ldexp(voxelsSquared, kFractionBits);
  // A leaf stays below 2^63 units (see kFractionBits); anything larger is split.
  const double high = std::floor(std::ldexp(units, -64));
  const double low = units - std::ldexp(high, 64);
  add128(squaredChangeHigh, squaredChangeLow, static_cast<std::uint64_t>(high), static_cast<std::uint64_t>(low));
}

StepTally& StepTally::operator+=(const StepTally& other) {
  dt = std::max(dt, other.dt);
  maxSpeed = std::max(maxSpeed, other.maxSpeed);
  maxChange = std::max(maxChange, other.maxChange);
  add128(squaredChangeHigh, squaredChangeLow, other.squaredChangeHigh, other.squaredChangeLow);
  points += other.points;
  pointsAtRest += other.pointsAtRest;
  activeSetVoxels += other.activeSetVoxels;
  movedOut += other.movedOut;
  movedIn += other.movedIn;
  conflicts += other.conflicts;
  return *this;
}

StepResult StepTally::result(double dx) const {
  StepResult r;
  r.dt = dt;
  r.maxSpeed = maxSpeed;
  r.maxChange = maxChange;
  const double voxelsSquared =
      std::ldexp(static_cast<double>(squaredChangeHigh), 64 - kFractionBits) +
      std::ldexp(static_cast<double>(squaredChangeLow), -kFractionBits);
  r.rmsChange = points ? dx * std::sqrt(voxelsSquared / static_cast<double>(points)) : 0.0;
  const std::uint64_t moving = points - pointsAtRest;  // points at rest add no squared change
  r.rmsChangeNotAtRest = moving ? dx * std::sqrt(voxelsSquared / static_cast<double>(moving)) : 0.0;
  r.pointsAtRest = static_cast<std::size_t>(pointsAtRest);
  r.activeSetVoxels = static_cast<std::size_t>(activeSetVoxels);
  r.movedOut = static_cast<std::size_t>(movedOut);
  r.movedIn = static_cast<std::size_t>(movedIn);
  r.conflicts = static_cast<std::size_t>(conflicts);
  return r;
}

}  // namespace levelfuse

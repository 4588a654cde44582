// levelfuse: the settings of a reconstruction resolved from its scans.

#include "ShortNumber.h"

#include <levelfuse/recon/ReconstructionOptions.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace levelfuse {

using detail::shortNumber;

namespace {

/// What the scans tell the derived settings.
struct ScanFacts {
  double raySpacing = 0.0;  ///< the median distance between neighbouring rays
  double sigma = 0.0;       ///< the median noise
  double extent = 0.0;      ///< the largest side of the readings' box
  bool scene = false;  ///< scans of a scene (ScanSummary::aScene)
};

/// The voxel size: as given, or the scans' ray spacing; checked.
double resolveVoxelSize(const std::optional<double>& given, const ScanFacts& scans) {
  const double voxelSize = given.value_or(scans.raySpacing);
  const bool derived = !given;
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize))
    throw std::invalid_argument("reconstruction: the voxel size must be positive");
  if (voxelSize < kSmallestVoxelSize)
    throw std::invalid_argument(
        "reconstruction: a voxel size of " + shortNumber(voxelSize) +
        (derived ? " (the scans' median distance between rays)" : "") +
        " is below the smallest a grid can have, " + shortNumber(kSmallestVoxelSize) +
        (derived ? ": the scans' coordinates are in units too small (give them in metres), or choose "
                   "a voxel size of at least "
                 : ": choose a voxel size of at least ") +
        shortNumber(kSmallestVoxelSize));
  if (scans.extent / voxelSize > 1e5)
    throw std::invalid_argument("reconstruction: a voxel size of " + std::to_string(voxelSize) +
                                " makes the data " + std::to_string(scans.extent / voxelSize) +
                                " voxels across; choose a voxel size of at least " + std::to_string(scans.extent / 1e5));
  return voxelSize;
}

/// The number of grids: as given, or a coarsest grid about 64 voxels across (one for a scene); checked.
int resolveLevels(const std::optional<int>& given, double voxelSize, const ScanFacts& scans) {
  const int levels = given.value_or(
      scans.scene ? 1 : 1 + std::max(0, static_cast<int>(std::lround(std::log2(scans.extent / (64.0 * voxelSize))))));
  if (levels < 1 || levels > 12) throw std::invalid_argument("reconstruction: the number of grids must be 1 to 12");
  return levels;
}

/// The window width: as given, or the scans' median sigma; checked against the data's extent.
double resolveEpsilon(const std::optional<double>& given, const ScanFacts& scans) {
  const double epsilon = given.value_or(scans.sigma);
  const bool derived = !given;
  if (!(epsilon > 0.0) || !std::isfinite(epsilon))
    throw std::invalid_argument("reconstruction: the window width epsilon must be positive");
  if (epsilon > scans.extent)
    throw std::invalid_argument(
        "reconstruction: a window width epsilon of " + shortNumber(epsilon) +
        (derived ? " (the scans' median sigma)" : "") + " is wider than the data, which span " +
        shortNumber(scans.extent) + ": a reading would speak for the whole scene; choose a window width epsilon of " +
        "at most " + shortNumber(scans.extent) + (derived ? ", or check the scans' sigma" : ""));
  return epsilon;
}

/// The prior's weight: as given, or max(0.5, sigma / voxel) (0 for a scene); checked.
double resolveBeta(const std::optional<double>& given, double voxelSize, const ScanFacts& scans) {
  const double beta = given.value_or(scans.scene ? 0.0 : std::max(0.5, scans.sigma / voxelSize));
  if (!(beta >= 0.0) || !std::isfinite(beta))
    throw std::invalid_argument("reconstruction: beta must be finite and not negative (0 turns the prior off)");
  return beta;
}

/// Throws std::invalid_argument unless the stopping rule's settings are usable.
void requireStoppingRule(const ReconstructionControls& given) {
  if (!(given.tolerance > 0.0)) throw std::invalid_argument("reconstruction: the tolerance must be positive");
  if (given.patience < 1) throw std::invalid_argument("reconstruction: the patience must be at least one iteration");
  if (!(given.drift > 0.0)) throw std::invalid_argument("reconstruction: the drift tolerance must be positive");
  if (given.minIterations < 0 || given.maxIterations < std::max(1, given.minIterations))
    throw std::invalid_argument("reconstruction: iterations must satisfy 0 <= min <= max, max >= 1");
}

/// What the scans' summary tells the derived settings; throws
/// std::invalid_argument for scans with no surface to reconstruct.
ScanFacts factsOf(const ScanSummary& scans) {
  // Counted, not judged by the box: the readings of one frame facing a wall square on may lie in a plane.
  if (scans.scans() == 0) throw std::invalid_argument("reconstruction: no range maps to reconstruct from");
  if (scans.readings() == 0) throw std::invalid_argument("reconstruction: the range maps hold no readings");
  const openvdb::BBoxd& bounds = scans.bounds();
  if (!(bounds.extents()[bounds.maxExtent()] > 0.0))
    throw std::invalid_argument("reconstruction: every reading lies at one point: there is no surface to reconstruct");
  ScanFacts facts;
  facts.raySpacing = scans.medianRaySpacing();
  facts.sigma = scans.medianSigma();
  facts.extent = bounds.extents()[bounds.maxExtent()];
  facts.scene = scans.aScene();
  return facts;
}

}  // namespace

ReconstructionSettings resolveReconstructionSettings(const ReconstructionOptions& given, const ScanSummary& scans) {
  const ScanFacts facts = factsOf(scans);
  ReconstructionSettings settings;
  static_cast<ReconstructionControls&>(settings) = given;
  settings.voxelSize = resolveVoxelSize(given.voxelSize, facts);
  settings.levels = resolveLevels(given.levels, settings.voxelSize, facts);
  settings.epsilon = resolveEpsilon(given.epsilon, facts);
  settings.beta = resolveBeta(given.beta, settings.voxelSize, facts);
  settings.dataTerm = given.dataTerm;
  if (settings.dataTerm == DataTermSource::kAuto)
    settings.dataTerm = scans.scans() > kGridsFromScans ? DataTermSource::kGrids : DataTermSource::kPerMap;
  requireStoppingRule(settings);
  return settings;
}

ReconstructionOptions optionsOf(const ReconstructionSettings& settings) {
  ReconstructionOptions options;
  static_cast<ReconstructionControls&>(options) = settings;
  options.voxelSize = settings.voxelSize;
  options.levels = settings.levels;
  options.beta = settings.beta;
  options.epsilon = settings.epsilon;
  options.dataTerm = settings.dataTerm;
  return options;
}

FusionSettings fusionSettingsOf(const ReconstructionSettings& settings) {
  FusionSettings grids;
  grids.voxelSize = settings.voxelSize;
  grids.levels = settings.levels;
  grids.epsilon = settings.epsilon;
  grids.window = settings.window;
  grids.grainSize = settings.engine.grainSize;
  return grids;
}

}  // namespace levelfuse

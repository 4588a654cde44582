// levelfuse: what a reconstruction's derived settings are taken from.

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/ScanSummary.h>

#include <stdexcept>
#include <string>

namespace levelfuse {

ScanSummary::ScanSummary(const std::vector<RangeMap>& maps) {
  for (const RangeMap& m : maps) add(m);
}

void ScanSummary::add(const RangeMap& map) {
  mReadings += map.validCount();
  mPoints += map.sampleCount();
  mBounds.expand(map.readingBounds());
  mRaySpacings.push_back(map.typicalRaySpacing());
  mSigmas.push_back(map.sigma());
  mScenes += map.ofAScene();
  mColoured += map.hasColours();
}

void ScanSummary::add(const ScanSummary& other) {
  mReadings += other.mReadings;
  mPoints += other.mPoints;
  mBounds.expand(other.mBounds);
  mRaySpacings.insert(mRaySpacings.end(), other.mRaySpacings.begin(), other.mRaySpacings.end());
  mSigmas.insert(mSigmas.end(), other.mSigmas.begin(), other.mSigmas.end());
  mScenes += other.mScenes;
  mColoured += other.mColoured;
}

namespace {
/// Numbers before the per-scan ones: the counts, the box's corners and the scans.
constexpr std::size_t kSummaryHead = 4 + 6 + 1;
}  // namespace

std::vector<double> ScanSummary::numbers() const {
  // Counts below 2^53 are exact as doubles; an empty box keeps its infinite corners.
  std::vector<double> n{static_cast<double>(mReadings), static_cast<double>(mPoints), static_cast<double>(mScenes),
                        static_cast<double>(mColoured)};
  for (int axis = 0; axis < 3; ++axis) n.push_back(mBounds.min()[axis]);
  for (int axis = 0; axis < 3; ++axis) n.push_back(mBounds.max()[axis]);
  n.push_back(static_cast<double>(mSigmas.size()));
  n.insert(n.end(), mRaySpacings.begin(), mRaySpacings.end());
  n.insert(n.end(), mSigmas.begin(), mSigmas.end());
  return n;
}

ScanSummary ScanSummary::fromNumbers(const std::vector<double>& n) {
  const auto count = [](double v) { return static_cast<std::size_t>(v); };
  if (n.size() < kSummaryHead || n.size() != kSummaryHead + 2 * count(n[kSummaryHead - 1]))
    throw std::invalid_argument("a scan summary of " + std::to_string(n.size()) + " numbers: they are no summary's");
  ScanSummary s;
  s.mReadings = count(n[0]);
  s.mPoints = count(n[1]);
  s.mScenes = count(n[2]);
  s.mColoured = count(n[3]);
  s.mBounds = openvdb::BBoxd(openvdb::Vec3d(n[4], n[5], n[6]), openvdb::Vec3d(n[7], n[8], n[9]));
  const std::size_t scans = count(n[kSummaryHead - 1]);
  const auto perScan = n.begin() + static_cast<std::ptrdiff_t>(kSummaryHead);
  s.mRaySpacings.assign(perScan, perScan + static_cast<std::ptrdiff_t>(scans));
  s.mSigmas.assign(perScan + static_cast<std::ptrdiff_t>(scans), n.end());
  return s;
}

double ScanSummary::medianRaySpacing() const { return median(mRaySpacings); }

double ScanSummary::medianSigma() const { return median(mSigmas); }

}  // namespace levelfuse

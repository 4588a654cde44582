// levelfuse: what a reconstruction's derived settings are taken from.

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/ScanSummary.h>

namespace levelfuse {

ScanSummary::ScanSummary(const std::vector<RangeMap>& maps) {
  for (const RangeMap& m : maps) add(m);
}

void ScanSummary::add(const RangeMap& map) {
  mReadings += map.validCount();
  mPoints += map.sampleCount();
  mBounds.expand(map.readingBounds());
  mRaySpacings.push_back(map.maxRaySpacing());
  mSigmas.push_back(map.sigma());
  mScenes += map.ofAScene();
  mColoured += map.hasColours();
}

double ScanSummary::medianRaySpacing() const { return median(mRaySpacings); }

double ScanSummary::medianSigma() const { return median(mSigmas); }

}  // namespace levelfuse

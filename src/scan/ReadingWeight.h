// levelfuse: the weight of one reading's term at a point (private to the data term).
#pragma once

#include <levelfuse/scan/RangeMap.h>

namespace levelfuse::detail {

/// c w gamma: the window w times the confidence c = 1 / (sigma^2 + |grad D|^2
/// sigma_x^2) (Eq. 38) times the ray density gamma; the term of g (Eq. 17) is
/// this times D.
inline double readingWeight(double window, const RangeMap::LocalSample& s, double positionVariance) {
  return window * s.gamma / (s.sigma * s.sigma + s.gradDSquared * positionVariance);
}

}  // namespace levelfuse::detail

// levelfuse: SlabField::computeRates for any speed.
//
// The library instantiates computeRates for the speeds of SpeedTerms.h.
// Include this header (in a .cc file of your own) for a speed of your own.
#pragma once

#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SparseFieldStep.h>

namespace levelfuse {

template <typename Speed>
double SlabField::computeRates(const Speed& speed) {
  detail::indexActivePoints(*mState);
  return detail::computeRates(*mState, speed);
}

}  // namespace levelfuse

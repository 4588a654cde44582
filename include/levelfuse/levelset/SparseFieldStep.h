// levelfuse: SparseField::step for any speed.
//
// The library instantiates step() for the speeds of SpeedTerms.h. Include this
// header (in a .cc file of your own; it is heavier than SparseField.h) to step
// under a speed type of your own.
#pragma once

#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/StepTally.h>
#include <levelfuse/levelset/detail/LeafNeighbourhood.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace levelfuse {
namespace detail {

/// Phase 1 (section 5, step 1): d psi/dt at every active point, stored in
/// state.pointValues in record order; returns the largest |d psi/dt| over the
/// leaves the field answers for (all, unless it is a slab). Marks in
/// state.atRest the leaves where the speed is at rest (speedAtRestIn).
template <typename Speed>
double computeRates(SparseFieldState& state, const Speed& speed) {
  LeafTable& table = state.table;
  std::vector<float> leafMax(table.size(), 0.0f);
  const openvdb::math::Transform& transform = state.grid->transform();
  const openvdb::math::MapBase& map = *transform.baseMap();  // the transform holds it
  const float h = static_cast<float>(state.dx);
  float* rates = state.pointValues.data();
  state.atRest.assign(table.size(), 0);

  forEachRecord(table, state.options.grainSize, [&](std::size_t r) {
    const LeafRecord& record = table[r];
    if (!anyOn(record.layer[0])) return;
    const openvdb::CoordBBox voxels(record.origin, record.origin.offsetBy(FloatLeaf::DIM - 1));
    if (speedAtRestIn(speed, voxels, transform)) {
      std::fill_n(rates + state.firstActive[r], state.activeCount[r], 0.0f);  // leafMax[r] stays 0
      state.atRest[r] = 1;
      return;
    }
    const ValueNeighbourhood neighbourhood(table, record);
    const auto& local = localSpeed(speed);  // one leaf's points, one task
    Stencil stencil;
    stencil.h = h;
    float maxRate = 0.0f;
    std::uint32_t slot = state.firstActive[r];
    forEachOn(record.layer[0], [&](unsigned offset) {
      neighbourhood.gather(offset, stencil);
      const openvdb::Coord ijk = record.origin + FloatLeaf::offsetToLocalCoord(offset);
      float rate = local(ActivePoint{stencil, ijk, transform, map});
      if (!std::isfinite(rate)) rate = 0.0f;  // a speed undefined here does not move the point
      rates[slot++] = rate;
      maxRate = std::max(maxRate, std::fabs(rate));
    });
    leafMax[r] = maxRate;
  });
  float maxRate = 0.0f;
  for (std::size_t r = 0; r < table.size(); ++r)
    if (state.owns(table[r])) maxRate = std::max(maxRate, leafMax[r]);
  return maxRate;
}

}  // namespace detail

template <typename Speed>
StepResult SparseField::step(const Speed& speed, double maxDt) {
  detail::SparseFieldState& state = *mState;
  detail::indexActivePoints(state);
  const double maxSpeed = detail::computeRates(state, speed);
  const double dt = detail::chooseTimeStep(state, maxSpeed, speed.curvatureWeight(), speedStiffness(speed), maxDt);
  return detail::applyRates(state, dt, maxSpeed).result(state.dx);
}

}  // namespace levelfuse

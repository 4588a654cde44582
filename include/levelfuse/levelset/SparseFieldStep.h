// levelfuse: SparseField::step for any speed.
//
// The library instantiates step() for the speeds of SpeedTerms.h. Include this
// header (in a .cc file of your own; it is heavier than SparseField.h) to step
// under a speed type of your own.
#pragma once

#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace levelfuse {
namespace detail {

/// Pointers to the value buffers of a leaf and its 26 neighbours, for reading
/// the stencils of the leaf's active points across leaf faces and edges.
class LeafNeighbourhood {
 public:
  LeafNeighbourhood(const LeafTable& table, const LeafRecord& record) {
    for (int s = 0; s < 27; ++s) {
      const std::int32_t n = record.neighbour[s];
      mValues[s] = n >= 0 ? table[n].leaf->buffer().data() : nullptr;
    }
  }

  /// Fills the 19-point stencil of the voxel at `offset` in the centre leaf.
  /// The layers cover every active point's stencil, so a missing neighbour leaf
  /// is never read for a consistent field; it reads as the centre's side of
  /// the background if it is.
  void gather(unsigned offset, float background, Stencil& s) const {
    const int i = static_cast<int>(offset >> 6), j = static_cast<int>((offset >> 3) & 7u),
              k = static_cast<int>(offset & 7u);
    const float* centre = mValues[kSelfSlot];
    if (i > 0 && i < 7 && j > 0 && j < 7 && k > 0 && k < 7) {
      for (int p = 0; p < Stencil::kSize; ++p) {
        const int* d = Stencil::kOffset[p];
        s.u[p] = centre[static_cast<int>(offset) + (d[0] << 6) + (d[1] << 3) + d[2]];
      }
      return;
    }
    const float outside = centre[offset] < 0.0f ? -background : background;
    for (int p = 0; p < Stencil::kSize; ++p) {
      const int* d = Stencil::kOffset[p];
      const int ni = i + d[0], nj = j + d[1], nk = k + d[2];
      const int slot = side(ni) * 9 + side(nj) * 3 + side(nk);
      const float* values = mValues[slot];
      s.u[p] = values ? values[((ni & 7) << 6) | ((nj & 7) << 3) | (nk & 7)] : outside;
    }
  }

 private:
  static int side(int c) { return c < 0 ? 0 : (c > 7 ? 2 : 1); }
  const float* mValues[27];
};

/// Phase 1 (section 5, step 1): d psi/dt at every active point, stored in
/// state.pointValues in record order; returns the largest |d psi/dt|.
template <typename Speed>
double computeRates(SparseFieldState& state, const Speed& speed) {
  LeafTable& table = state.table;
  std::vector<float> leafMax(table.size(), 0.0f);
  const openvdb::math::Transform& transform = state.grid->transform();
  const float h = static_cast<float>(state.dx);
  const float background = state.background;
  float* rates = state.pointValues.data();

  forEachRecord(table, state.options.grainSize, [&](std::size_t r) {
    const LeafRecord& record = table[r];
    if (!anyOn(record.layer[0])) return;
    const LeafNeighbourhood neighbourhood(table, record);
    Stencil stencil;
    stencil.h = h;
    float maxRate = 0.0f;
    std::uint32_t slot = record.firstActive;
    forEachOn(record.layer[0], [&](unsigned offset) {
      neighbourhood.gather(offset, background, stencil);
      const openvdb::Coord ijk = record.origin + openvdb::Coord(static_cast<int>(offset >> 6),
                                                                static_cast<int>((offset >> 3) & 7u),
                                                                static_cast<int>(offset & 7u));
      float rate = speed(ActivePoint{stencil, ijk, transform});
      if (!std::isfinite(rate)) rate = 0.0f;  // a speed undefined here does not move the point
      rates[slot++] = rate;
      maxRate = std::max(maxRate, std::fabs(rate));
    });
    leafMax[r] = maxRate;
  });
  float maxRate = 0.0f;
  for (float m : leafMax) maxRate = std::max(maxRate, m);
  return maxRate;
}

}  // namespace detail

template <typename Speed>
StepResult SparseField::step(const Speed& speed, double maxDt) {
  detail::SparseFieldState& state = *mState;
  detail::indexActivePoints(state);
  const double maxSpeed = detail::computeRates(state, speed);
  const double dt = detail::chooseTimeStep(state, maxSpeed, speed.curvatureWeight(), maxDt);
  return detail::applyRates(state, dt, maxSpeed);
}

}  // namespace levelfuse

// levelfuse: checks of the sparse field's invariants.

#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace levelfuse {

InvariantReport checkInvariants(const SparseField& field) {
  const detail::SparseFieldState& state = field.state();
  const detail::LeafTable& table = state.table;
  const int N = field.layers();
  const double dx = state.dx;
  const double tol = 1.0e-5 * dx;
  InvariantReport report;
  openvdb::FloatGrid::ConstAccessor acc = state.grid->getConstAccessor();

  const auto note = [&](std::size_t& counter, const openvdb::Coord& ijk, const std::string& what) {
    if (report.firstViolation.empty()) {
      std::ostringstream s;
      s << what << " at " << ijk;
      report.firstViolation = s.str();
    }
    ++counter;
  };

  for (std::size_t r = 0; r < table.size(); ++r) {
    const detail::LeafRecord& record = table[r];
    if (!record.live()) continue;
    if (!detail::anyOn(record.leaf->getValueMask()))
      note(report.structureViolations, record.origin, "leaf without layers");
    for (openvdb::Index o = 0; o < detail::FloatLeaf::SIZE; ++o) {
      const openvdb::Coord ijk = record.origin + detail::FloatLeaf::offsetToLocalCoord(o);
      const float v = record.leaf->getValue(o);
      const bool inside = v < 0.0f;
      const int layer = field.layerOf(ijk);
      const bool inBand = std::abs(layer) <= N;
      if (inBand != record.leaf->isValueOn(o)) note(report.structureViolations, ijk, "band and layers disagree");
      // Value ranges.
      if (layer == 0) {
        ++report.activeSetVoxels;
        if (std::fabs(v) > 0.5 * dx + tol) note(report.rangeViolations, ijk, "active value outside [-1/2, 1/2]");
      } else if (inBand) {
        const double lo = (std::abs(layer) - 0.5) * dx - tol, hi = (std::abs(layer) + 0.5) * dx + tol;
        if (std::fabs(v) < lo || std::fabs(v) > hi || (layer < 0) != inside)
          note(report.rangeViolations, ijk, "layer value outside its range");
      } else if (std::fabs(std::fabs(v) - state.background) > tol) {
        note(report.rangeViolations, ijk, "voxel outside the layers is not at the background");
      }
      // Neighbourhood.
      bool oppositeNeighbour = false, innerNeighbour = false;
      for (const auto& e : detail::kFaceOffset) {
        const openvdb::Coord n = ijk.offsetBy(e[0], e[1], e[2]);
        const float w = acc.getValue(n);
        const int nl = field.layerOf(n);
        if ((w < 0.0f) != inside) {
          oppositeNeighbour = true;
          if (layer != 0 && nl != 0) note(report.separationViolations, ijk, "sign change without an active point");
        }
        if (inBand && layer != 0 && std::abs(nl) == std::abs(layer) - 1) innerNeighbour = true;
        if (inBand && std::abs(std::abs(nl) - std::abs(layer)) > 1 && !(std::abs(layer) == N && std::abs(nl) == N + 1))
          note(report.structureViolations, ijk, "neighbours more than one layer apart");
      }
      if (layer == 0 && !oppositeNeighbour) ++report.inefficientActive;
      if (inBand && layer != 0 && !innerNeighbour)
        note(report.structureViolations, ijk, "layer voxel without a neighbour in the next inner layer");
    }
  }
  return report;
}

}  // namespace levelfuse

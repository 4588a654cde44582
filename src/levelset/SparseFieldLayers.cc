// levelfuse: the sparse field's update of values and layers (section 5).
//
// Each function below is one bulk-synchronous phase: a parallel pass over leaf
// records in which every task writes only its own leaf and record and reads
// its neighbours' state as the previous phase left it. Reductions are gathered
// per leaf and summed serially, so results do not depend on the thread count.

#include <levelfuse/levelset/detail/LeafNeighbourhood.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace levelfuse::detail {

namespace {

LeafMask minus(LeafMask a, const LeafMask& b) {
  a -= b;
  return a;
}

/// The masks selected by `member` of a record's six face neighbours (null where absent).
template <typename Member>
void faceMasks(const LeafTable& table, const LeafRecord& record, Member member, const LeafMask* out[kFaceCount]) {
  for (int f = 0; f < kFaceCount; ++f) {
    const std::int32_t n = record.neighbour[kFaceSlot[f]];
    out[f] = n >= 0 ? &(table[n].*member) : nullptr;
  }
}

/// Value of a voxel entering a layer next to the voxels of `inner`
/// (section 5, step 3): the nearest inner neighbour's value plus one voxel
/// outside, minus one voxel inside. In OpenVDB's sign the nearest neighbour is
/// the one with the smallest value outside and the largest inside.
float fromNearestInner(const FaceNeighbourhood& inner, unsigned offset, bool inside, float dx) {
  return inside ? inner.nearest(offset, true) - dx : inner.nearest(offset, false) + dx;
}

/// Creates the leaves the outermost layer grows into and links their records.
void allocateRequestedLeaves(SparseFieldState& state) {
  static constexpr int kStep[kFaceCount][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0},
                                               {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};
  LeafTable& table = state.table;
  std::vector<openvdb::Coord> origins;
  const int dim = static_cast<int>(FloatLeaf::DIM);
  for (std::size_t r = 0; r < state.faceRequest.size(); ++r) {
    const std::uint8_t request = state.faceRequest[r];
    if (request == 0) continue;
    for (int f = 0; f < kFaceCount; ++f)
      if (request & (1u << f))
        origins.push_back(table[r].origin.offsetBy(kStep[f][0] * dim, kStep[f][1] * dim, kStep[f][2] * dim));
    state.faceRequest[r] = 0;
  }
  std::sort(origins.begin(), origins.end());
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
  for (const openvdb::Coord& origin : origins) {
    if (table.find(origin) >= 0) continue;
    // A new leaf takes the value of the inactive tile it replaces: +-background.
    table.add(state.tree().touchLeaf(origin));
  }
  state.fitRecordArrays();
}

}  // namespace

std::size_t indexActivePoints(SparseFieldState& state) {
  std::size_t total = 0;
  for (std::size_t r = 0; r < state.activeCount.size(); ++r) {
    state.firstActive[r] = static_cast<std::uint32_t>(total);
    total += state.activeCount[r];
  }
  state.pointValues.resize(total);
  return total;
}

double chooseTimeStep(const SparseFieldState& state, double maxSpeed, double curvatureWeight, double stiffness,
                      double maxDt) {
  double dt = maxDt;
  // Eqs. 31-32: the fastest front over the active set may move maxStepChange voxels.
  if (maxSpeed > 0.0) dt = std::min(dt, state.options.maxStepChange * state.dx / maxSpeed);
  // Stability of the explicit curvature term (Eq. 26) and of a stiff force,
  // combined as rates.
  const double curvatureDt = state.options.curvatureStepLimit * state.dx * state.dx / curvatureWeight;
  const double stiffnessDt = state.options.stiffnessStepLimit / stiffness;
  if (curvatureWeight > 0.0 && stiffness > 0.0) dt = std::min(dt, 1.0 / (1.0 / curvatureDt + 1.0 / stiffnessDt));
  else if (curvatureWeight > 0.0) dt = std::min(dt, curvatureDt);
  else if (stiffness > 0.0) dt = std::min(dt, stiffnessDt);
  if (!std::isfinite(dt) || dt < 0.0) dt = 0.0;
  return dt;
}

StepResult applyRates(SparseFieldState& state, double dt, double maxSpeed) {
  LeafTable& table = state.table;
  const std::size_t grain = state.options.grainSize;
  const float half = static_cast<float>(0.5 * state.dx);
  const float fdt = static_cast<float>(dt);
  const float dx = static_cast<float>(state.dx);
  const float* rates = state.pointValues.data();

  struct LeafTally {
    double sumSq = 0.0;
    float maxChange = 0.0f;
    std::uint32_t points = 0, out = 0, in = 0, conflicts = 0;
  };
  std::vector<LeafTally> tally(table.size());

  // Step 2: add the change to every active point; points leaving [-1/2, 1/2]
  // voxel become candidates to move out (up) or in (down).
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    record.up.setOff();
    record.down.setOff();
    record.conflict.setOff();
    float* values = record.values;
    LeafTally& t = tally[r];
    std::uint32_t slot = state.firstActive[r];
    forEachOn(record.layer[0], [&](unsigned o) {
      const float change = fdt * rates[slot++];
      const float v = values[o] + change;
      values[o] = v;
      t.sumSq += static_cast<double>(change) * change;
      t.maxChange = std::max(t.maxChange, std::fabs(change));
      ++t.points;
      if (v > half) {
        record.up.setOn(o);
        t.out = 1;
      } else if (v < -half) {
        record.down.setOn(o);
        t.in = 1;
      }
    });
  });

  // Two adjacent points leaving on opposite sides would leave a sign change
  // without an active point between them (the Appendix's movements must stay
  // separate). Both stay active, held at the edge of the range. Nothing to do
  // unless points leave on both sides somewhere.
  bool anyOut = false, anyIn = false;
  for (const LeafTally& t : tally) {
    anyOut = anyOut || t.out;
    anyIn = anyIn || t.in;
  }
  if (anyOut && anyIn) forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    if (!anyOn(record.up) && !anyOn(record.down)) return;
    const LeafMask* ups[kFaceCount];
    const LeafMask* downs[kFaceCount];
    faceMasks(table, record, &LeafRecord::up, ups);
    faceMasks(table, record, &LeafRecord::down, downs);
    LeafMask conflict = record.up & dilateFaces(record.down, downs);
    conflict |= record.down & dilateFaces(record.up, ups);
    if (!anyOn(conflict)) return;
    float* values = record.values;
    forEachOn(conflict, [&](unsigned o) { values[o] = record.up.isOn(o) ? half : -half; });
    record.conflict = conflict;
    tally[r].conflicts = conflict.countOn();
  });

  // Step 4 for the active set: points that leave are replaced by their
  // neighbours across the zero crossing (the movement of Eq. 42), valued from
  // the active points next to them (step 3).
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    const LeafMask leavingOut = minus(record.up, record.conflict);
    const LeafMask leavingIn = minus(record.down, record.conflict);
    record.next = minus(minus(record.layer[0], leavingOut), leavingIn);
    tally[r].out = leavingOut.countOn();
    tally[r].in = leavingIn.countOn();

    LeafMask faceOut[kFaceCount], faceIn[kFaceCount];
    const LeafMask* outs[kFaceCount];
    const LeafMask* ins[kFaceCount];
    for (int f = 0; f < kFaceCount; ++f) {
      const std::int32_t n = record.neighbour[kFaceSlot[f]];
      outs[f] = ins[f] = nullptr;
      if (n < 0) continue;
      faceOut[f] = minus(table[n].up, table[n].conflict);
      faceIn[f] = minus(table[n].down, table[n].conflict);
      outs[f] = &faceOut[f];
      ins[f] = &faceIn[f];
    }
    const LeafMask besideOut = dilateFaces(leavingOut, outs);
    const LeafMask besideIn = dilateFaces(leavingIn, ins);
    LeafMask candidates = (besideOut | besideIn) & record.leaf->getValueMask();
    candidates -= record.layer[0];
    if (!anyOn(candidates)) return;

    const FaceNeighbourhood oldActive(table, record, [](const LeafRecord& n) -> const LeafMask& { return n.layer[0]; });
    float* values = record.values;
    forEachOn(candidates, [&](unsigned o) {
      const bool inside = values[o] < 0.0f;
      if (inside ? !besideOut.isOn(o) : !besideIn.isOn(o)) return;
      values[o] = fromNearestInner(oldActive, o, inside, dx);
      record.next.setOn(o);
    });
  });

  rebuildLayers(state);

  StepResult result;
  result.dt = dt;
  result.maxSpeed = maxSpeed;
  double sumSq = 0.0;
  std::size_t points = 0;
  for (const LeafTally& t : tally) {
    sumSq += t.sumSq;
    points += t.points;
    result.maxChange = std::max(result.maxChange, static_cast<double>(t.maxChange));
    result.movedOut += t.out;
    result.movedIn += t.in;
    result.conflicts += t.conflicts;
  }
  result.rmsChange = points ? std::sqrt(sumSq / static_cast<double>(points)) : 0.0;
  for (const std::uint32_t n : state.activeCount) result.activeVoxels += n;
  return result;
}

void rebuildLayers(SparseFieldState& state) {
  LeafTable& table = state.table;
  const std::size_t grain = state.options.grainSize;
  const int layers = state.options.layers;
  const float dx = static_cast<float>(state.dx);

  // Step 3: layer i is every voxel next to layer i-1 that is in no inner layer,
  // valued from its nearest neighbour in layer i-1. Points of the old layers
  // with no inner neighbour fall outward or out of the layers (step 4). The
  // pass of the outermost layer also commits the leaf: its layers become the
  // band (the value tree's active voxels), voxels that left every layer take
  // the background value of their side. Neighbours read only layers and
  // values of layer voxels in that pass, so committing there is safe.
  const float background = state.background;
  std::vector<std::uint8_t> empty(table.size(), 0);
  for (int i = 1; i <= layers; ++i) {
    if (i == layers) {
      allocateRequestedLeaves(state);
      empty.assign(table.size(), 0);
    }
    const auto innerOf = [i](const LeafRecord& n) -> const LeafMask& { return i == 1 ? n.next : n.layer[i - 1]; };
    forEachRecord(table, grain, [&](std::size_t r) {
      LeafRecord& record = table[r];
      const LeafMask* innerFaces[kFaceCount];
      for (int f = 0; f < kFaceCount; ++f) {
        const std::int32_t n = record.neighbour[kFaceSlot[f]];
        innerFaces[f] = n >= 0 ? &innerOf(table[n]) : nullptr;
      }
      LeafMask ring = dilateFaces(innerOf(record), innerFaces);
      ring -= record.next;
      for (int j = 1; j < i; ++j) ring -= record.layer[j];
      record.layer[i] = ring;
      float* values = record.values;
      if (anyOn(ring)) {
        const FaceNeighbourhood inner(table, record, innerOf);
        forEachOn(ring, [&](unsigned o) { values[o] = fromNearestInner(inner, o, values[o] < 0.0f, dx); });
      }
      if (i == layers - 1) {
        // The outermost layer grows one voxel past this one: ask for the leaves it reaches.
        std::uint8_t request = 0;
        for (int f = 0; f < kFaceCount; ++f)
          if (record.neighbour[kFaceSlot[f]] < 0 && touchesFace(ring, f)) request |= std::uint8_t(1u << f);
        state.faceRequest[r] = request;
      }
      if (i == layers) {
        LeafMask band = record.next;
        for (int j = 1; j <= layers; ++j) band |= record.layer[j];
        const LeafMask retired = minus(record.leaf->getValueMask(), band);
        forEachOn(retired, [&](unsigned o) { values[o] = values[o] < 0.0f ? -background : background; });
        record.leaf->setValueMask(band);
        record.layer[0] = record.next;
        state.activeCount[r] = record.next.countOn();
        empty[r] = !anyOn(band);
      }
    });
  }

  // A leaf left without layers lies wholly on one side of the surface: it
  // becomes an inactive tile of that side.
  for (std::size_t r = 0; r < table.size(); ++r) {
    if (!empty[r] || !table[r].live()) continue;
    const float value = table[r].values[0] < 0.0f ? -background : background;
    const openvdb::Coord origin = table[r].origin;
    table.remove(static_cast<std::int32_t>(r));
    state.activeCount[r] = 0;
    state.tree().addTile(1, origin, value, false);
  }
}

}  // namespace levelfuse::detail

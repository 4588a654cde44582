// levelfuse: the sparse field's update of values and layers (section 5).
//
// Each function below is one bulk-synchronous phase: a parallel pass over leaf
// records in which every task writes only its own leaf and record and reads
// its neighbours' state as the previous phase left it. Reductions are gathered
// per leaf and summed serially, so results do not depend on the thread count.

#include <levelfuse/core/DebugCheck.h>
#include <levelfuse/levelset/StepTally.h>
#include <levelfuse/levelset/TimeStep.h>
#include <levelfuse/levelset/detail/LeafNeighbourhood.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace levelfuse::detail {

namespace {

LeafMask minus(LeafMask a, const LeafMask& b) {
  a -= b;
  return a;
}

/// The masks `maskOf(neighbour)` of a record's six face neighbours, in `out`
/// (null where a neighbour is absent). A mask `maskOf` computes rather than
/// references is kept in `storage`, kFaceCount masks (null for references).
template <typename MaskOf>
void faceMasks(const LeafTable& table, const LeafRecord& record, MaskOf maskOf, LeafMask* storage,
               const LeafMask* out[kFaceCount]) {
  for (int f = 0; f < kFaceCount; ++f) {
    const std::int32_t n = record.neighbour[kFaceSlot[f]];
    if (n < 0) {
      out[f] = nullptr;
    } else if constexpr (std::is_lvalue_reference_v<decltype(maskOf(table[n]))>) {
      out[f] = &maskOf(table[n]);
    } else {
      storage[f] = maskOf(table[n]);
      out[f] = &storage[f];
    }
  }
}

/// Value of a voxel entering a layer next to the voxels of `inner` (the layer
/// rule, LeafNeighbourhood.h). The side is passed on as a constant, so that
/// each branch compiles to a rule of fixed sign.
float fromNearestInner(const FaceNeighbourhood& inner, unsigned offset, bool inside, float dx) {
  return inside ? layerValue(inner.nearest(offset, true), true, dx) : layerValue(inner.nearest(offset, false), false, dx);
}

/// True if the voxels of `ring` on face f lie inside. The layers reach a
/// missing neighbour leaf only where the active set keeps off the face, so no
/// sign changes across the face's voxels: they all lie on one side, which is
/// the side of the whole leaf beyond (no voxel there is in the layers yet).
bool faceInside(const LeafRecord& record, const LeafMask& ring, int f) {
  const openvdb::Index first = (ring & faceVoxels(f)).findFirstOn();
  return first < FloatLeaf::SIZE && record.values[first] < 0.0f;
}

/// A leaf the outermost layer grows into, the side it lies on, and the leaf
/// that asked for it.
struct LeafRequest {
  openvdb::Coord origin;
  openvdb::Coord askedBy;
  bool inside;
  bool operator<(const LeafRequest& o) const {
    return origin < o.origin || (origin == o.origin && askedBy < o.askedBy);
  }
};

/// Creates the leaves the outermost layer grows into, inside the domain, and
/// links their records. A new leaf lies wholly on the side of the leaf that
/// asked for it (the one with the least origin, if several did, so that the
/// choice does not depend on the order of the records); every voxel takes the
/// background value of that side.
void allocateRequestedLeaves(SparseFieldState& state) {
  LeafTable& table = state.table;
  std::vector<LeafRequest> requests;
  for (std::size_t r = 0; r < state.faceRequest.size(); ++r) {
    const std::uint8_t request = state.faceRequest[r];
    if (request == 0) continue;
    for (int f = 0; f < kFaceCount; ++f)
      if (request & (1u << f)) {
        const openvdb::Coord origin = leafAcross(table[r].origin, f);
        if (state.domain.contains(origin.x()))
          requests.push_back(LeafRequest{origin, table[r].origin, (state.faceInside[r] & (1u << f)) != 0});
      }
    state.faceRequest[r] = 0;
    state.faceInside[r] = 0;
  }
  std::sort(requests.begin(), requests.end());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const LeafRequest& request = requests[i];
    if (i > 0 && requests[i - 1].origin == request.origin) continue;
    if (table.find(request.origin) >= 0) continue;
    FloatLeaf* leaf = state.tree().touchLeaf(request.origin);
    leaf->fill(request.inside ? -state.background : state.background, false);
    table.add(leaf);
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
  const SparseFieldOptions& o = state.options;
  return stableTimeStep(TimeStepLimits{o.maxStepChange, o.curvatureStepLimit, o.stiffnessStepLimit}, state.dx,
                        maxSpeed, curvatureWeight, stiffness, maxDt);
}

namespace {

/// What one leaf's active points did in a step; each field means one thing.
struct LeafTally {
  double sumSq = 0.0;          ///< sum of the squared changes
  float maxChange = 0.0f;      ///< largest change
  std::uint32_t points = 0;    ///< active points changed
  std::uint32_t pointsAtRest = 0;  ///< of those, points the speed left at rest
  std::uint32_t wantOut = 0;   ///< points whose value left the range outward (up)
  std::uint32_t wantIn = 0;    ///< ... inward (down)
  std::uint32_t conflicts = 0; ///< of those, points held because a neighbour left the other way
  std::uint32_t movedOut = 0;  ///< points that left the active set outward
  std::uint32_t movedIn = 0;   ///< ... inward
  bool valuesChanged = false;  ///< some active value changed, if only in the sign of a zero
};

/// Step 2: adds dt times its rate to every active point; the points whose
/// value leaves [-1/2, 1/2] voxel become candidates to move out (up) or in (down).
void addChanges(SparseFieldState& state, float dt, std::vector<LeafTally>& tally) {
  const float half = static_cast<float>(0.5 * state.dx);
  const float* rates = state.pointValues.data();
  forEachRecord(state.table, state.options.grainSize, [&](std::size_t r) {
    LeafRecord& record = state.table[r];
    record.up.setOff();
    record.down.setOff();
    record.conflict.setOff();
    float* values = record.values;
    LeafTally& t = tally[r];
    std::uint32_t slot = state.firstActive[r];
    forEachOn(record.layer[0], [&](unsigned o) {
      const float change = dt * rates[slot++];
      const float old = values[o], v = old + change;
      values[o] = v;
      t.valuesChanged |= v != old || std::signbit(v) != std::signbit(old);
      t.sumSq += static_cast<double>(change) * change;
      t.maxChange = std::max(t.maxChange, std::fabs(change));
      ++t.points;
      if (v > half) {
        record.up.setOn(o);
        ++t.wantOut;
      } else if (v < -half) {
        record.down.setOn(o);
        ++t.wantIn;
      }
    });
    if (state.atRest[r]) t.pointsAtRest = t.points;
  });
}

/// Two adjacent points leaving on opposite sides would leave a sign change
/// without an active point between them (the Appendix's movements must stay
/// separate). Both stay active, held at the edge of the range. Nothing to do
/// unless points leave on both sides somewhere. Each task writes only its own
/// leaf's values and conflict mask and reads its neighbours' up and down masks.
void holdConflicts(SparseFieldState& state, std::vector<LeafTally>& tally) {
  bool anyOut = false, anyIn = false;
  for (const LeafTally& t : tally) {
    anyOut = anyOut || t.wantOut > 0;
    anyIn = anyIn || t.wantIn > 0;
  }
  if (!anyOut || !anyIn) return;
  const float half = static_cast<float>(0.5 * state.dx);
  const LeafTable& table = state.table;
  forEachRecord(state.table, state.options.grainSize, [&](std::size_t r) {
    LeafRecord& record = state.table[r];
    if (!anyOn(record.up) && !anyOn(record.down)) return;
    const LeafMask* ups[kFaceCount];
    const LeafMask* downs[kFaceCount];
    faceMasks(table, record, [](const LeafRecord& n) -> const LeafMask& { return n.up; }, nullptr, ups);
    faceMasks(table, record, [](const LeafRecord& n) -> const LeafMask& { return n.down; }, nullptr, downs);
    LeafMask conflict = record.up & dilateFaces(record.down, downs);
    conflict |= record.down & dilateFaces(record.up, ups);
    if (!anyOn(conflict)) return;
    float* values = record.values;
    forEachOn(conflict, [&](unsigned o) { values[o] = record.up.isOn(o) ? half : -half; });
    record.conflict = conflict;
    tally[r].conflicts = conflict.countOn();
  });
}

/// Step 4 for the active set: points that leave are replaced by their
/// neighbours across the zero crossing (the movement of Eq. 42), valued from
/// the active points next to them (step 3). In place: a task writes only
/// voxels outside every active set (the candidates) and its own leaf's `next`,
/// and reads only active points' values and the masks of step 2.
void replaceLeavingPoints(SparseFieldState& state, std::vector<LeafTally>& tally) {
  const float dx = static_cast<float>(state.dx);
  const LeafTable& table = state.table;
  forEachRecord(state.table, state.options.grainSize, [&](std::size_t r) {
    LeafRecord& record = state.table[r];
    const LeafMask leavingOut = minus(record.up, record.conflict);
    const LeafMask leavingIn = minus(record.down, record.conflict);
    record.next = minus(minus(record.layer[0], leavingOut), leavingIn);
    tally[r].movedOut = leavingOut.countOn();
    tally[r].movedIn = leavingIn.countOn();

    LeafMask faceOut[kFaceCount], faceIn[kFaceCount];
    const LeafMask* outs[kFaceCount];
    const LeafMask* ins[kFaceCount];
    faceMasks(table, record, [](const LeafRecord& n) { return minus(n.up, n.conflict); }, faceOut, outs);
    faceMasks(table, record, [](const LeafRecord& n) { return minus(n.down, n.conflict); }, faceIn, ins);
    const LeafMask besideOut = dilateFaces(leavingOut, outs);
    const LeafMask besideIn = dilateFaces(leavingIn, ins);
    LeafMask candidates = (besideOut | besideIn) & record.leaf->getValueMask();
    candidates -= record.layer[0];
    if (!anyOn(candidates)) return;

    const FaceNeighbourhood oldActive(table, record, [](const LeafRecord& n) -> const LeafMask& { return n.layer[0]; });
    float* values = record.values;
    forEachOn(candidates, [&](unsigned o) {
      LEVELFUSE_DEBUG_CHECK(!record.layer[0].isOn(o), "a value the other tasks read is written in place");
      const bool inside = values[o] < 0.0f;
      if (inside ? !besideOut.isOn(o) : !besideIn.isOn(o)) return;
      values[o] = fromNearestInner(oldActive, o, inside, dx);
      record.next.setOn(o);
    });
  });
}

/// Marks in state.layersSettled the leaves whose layers the layer rule would
/// rebuild as they are: no leaf of their 3 x 3 x 3 neighbourhood changed in
/// the step (its active values, including a zero's sign, and its active set
/// stayed). A leaf's layers and their values follow from the active points
/// and values within N <= 3 voxels of them and from the signs of its own
/// voxels, all within that neighbourhood. A slab's ghosts, refreshed from
/// its neighbours between steps, count as changed.
void markSettledLeaves(SparseFieldState& state, const std::vector<LeafTally>& tally) {
  const LeafTable& table = state.table;
  state.layersSettled.assign(table.size(), 0);
  if (!state.options.keepSettledLayers) return;
  std::vector<std::uint8_t> changed(table.size(), 0);
  forEachRecord(table, state.options.grainSize, [&](std::size_t r) {
    const LeafRecord& record = table[r];
    const LeafTally& t = tally[r];
    changed[r] = !state.owns(record) || t.valuesChanged || t.conflicts > 0 || record.next != record.layer[0];
  });
  forEachRecord(table, state.options.grainSize, [&](std::size_t r) {
    const LeafRecord& record = table[r];
    bool settled = true;
    for (const std::int32_t n : record.neighbour) settled = settled && (n < 0 || !changed[n]);
    state.layersSettled[r] = settled;
  });
}

/// The tally of the leaves the field answers for (all of them, unless it is a slab).
StepTally summarise(const SparseFieldState& state, const std::vector<LeafTally>& tally, double dt,
                    double maxSpeed) {
  StepTally result;
  result.dt = dt;
  result.maxSpeed = maxSpeed;
  const double voxelArea = state.dx * state.dx;
  for (std::size_t r = 0; r < tally.size(); ++r) {
    if (!state.owns(state.table[r])) continue;
    const LeafTally& t = tally[r];
    result.addSquaredChanges(t.sumSq / voxelArea);
    result.points += t.points;
    result.pointsAtRest += t.pointsAtRest;
    result.maxChange = std::max(result.maxChange, static_cast<double>(t.maxChange));
    result.movedOut += t.movedOut;
    result.movedIn += t.movedIn;
    result.conflicts += t.conflicts;
    result.activeSetVoxels += state.activeCount[r];
  }
  return result;
}

}  // namespace

StepTally applyRates(SparseFieldState& state, double dt, double maxSpeed) {
  std::vector<LeafTally> tally(state.table.size());
  addChanges(state, static_cast<float>(dt), tally);  // step 2
  holdConflicts(state, tally);
  replaceLeavingPoints(state, tally);                // step 4 for the active set
  markSettledLeaves(state, tally);
  rebuildLayers(state);                              // steps 3 and 4 for the layers
  return summarise(state, tally, dt, maxSpeed);
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
  // A settled leaf (markSettledLeaves) keeps its layers and their values:
  // the rule would give them again. New leaves are never settled.
  const auto settled = [&state](std::size_t r) { return r < state.layersSettled.size() && state.layersSettled[r]; };
  std::vector<std::uint8_t> empty(table.size(), 0);
  for (int i = 1; i <= layers; ++i) {
    if (i == layers) {
      allocateRequestedLeaves(state);
      empty.assign(table.size(), 0);
    }
    const auto innerOf = [i](const LeafRecord& n) -> const LeafMask& { return i == 1 ? n.next : n.layer[i - 1]; };
    forEachRecord(table, grain, [&](std::size_t r) {
      LeafRecord& record = table[r];
      float* values = record.values;
      if (!settled(r)) {
        const LeafMask* innerFaces[kFaceCount];
        faceMasks(table, record, innerOf, nullptr, innerFaces);
        LeafMask ring = dilateFaces(innerOf(record), innerFaces);
        ring -= record.next;
        for (int j = 1; j < i; ++j) ring -= record.layer[j];
        record.layer[i] = ring;
        if (anyOn(ring)) {
          const FaceNeighbourhood inner(table, record, innerOf);
          forEachOn(ring, [&](unsigned o) { values[o] = fromNearestInner(inner, o, values[o] < 0.0f, dx); });
        }
      }
      const LeafMask& ring = record.layer[i];
      if (i == layers - 1) {
        // The outermost layer grows one voxel past this one: ask for the leaves it reaches.
        std::uint8_t request = 0, inside = 0;
        for (int f = 0; f < kFaceCount; ++f)
          if (record.neighbour[kFaceSlot[f]] < 0 && touchesFace(ring, f)) {
            request |= std::uint8_t(1u << f);
            if (faceInside(record, ring, f)) inside |= std::uint8_t(1u << f);
          }
        state.faceRequest[r] = request;
        state.faceInside[r] = inside;
      }
      if (i == layers) {
        LeafMask band = record.next;
        for (int j = 1; j <= layers; ++j) band |= record.layer[j];
        const LeafMask retired = minus(record.leaf->getValueMask(), band);
        LEVELFUSE_DEBUG_CHECK(layers >= 2 && !anyOn(retired & record.layer[layers - 1]),
                              "the commit writes what the other tasks of its pass read");
        forEachOn(retired, [&](unsigned o) { values[o] = values[o] < 0.0f ? -background : background; });
        record.leaf->setValueMask(band);
        record.layer[0] = record.next;
        state.activeCount[r] = record.next.countOn();
        empty[r] = !anyOn(band);
      }
    });
  }

  state.layersSettled.clear();  // a mark holds for one step's rebuild only

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

// levelfuse: the sparse field's update of values and layers (section 5).
//
// Each function below is one bulk-synchronous phase: a parallel pass over leaf
// records in which every task writes only its own leaf and record and reads
// its neighbours' state as the previous phase left it. Reductions are gathered
// per leaf and summed serially, so results do not depend on the thread count.

#include <levelfuse/levelset/detail/SparseFieldState.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace levelfuse::detail {

namespace {

LeafMask minus(LeafMask a, const LeafMask& b) {
  a -= b;
  return a;
}

/// The value buffers and records of a leaf and its six face neighbours.
class FaceNeighbours {
 public:
  FaceNeighbours(LeafTable& table, const LeafRecord& record) {
    for (int f = 0; f < kFaceCount; ++f) {
      const std::int32_t n = record.neighbour[kFaceSlot[f]];
      mRecord[f] = n >= 0 ? &table[n] : nullptr;
      mValues[f] = n >= 0 ? table[n].leaf->buffer().data() : nullptr;
    }
    mRecord[kFaceCount] = &record;
    mValues[kFaceCount] = record.leaf->buffer().data();
  }

  /// The masks selected by `member` of the six face neighbours (null where absent).
  template <typename Member>
  void masks(Member member, const LeafMask* out[kFaceCount]) const {
    for (int f = 0; f < kFaceCount; ++f) out[f] = mRecord[f] ? &(mRecord[f]->*member) : nullptr;
  }

  /// Calls f(record, values, offset) for each face neighbour of voxel `offset`
  /// in the order -x, +x, -y, +y, -z, +z; missing() for a neighbour whose leaf
  /// is not allocated.
  template <typename F, typename M>
  void forEachNeighbour(unsigned offset, F&& f, M&& missing) const {
    const unsigned i = offset >> 6, j = (offset >> 3) & 7u, k = offset & 7u;
    visit(i > 0 ? kFaceCount : kFaceXm, i > 0 ? offset - 64 : offset + 448, f, missing);
    visit(i < 7 ? kFaceCount : kFaceXp, i < 7 ? offset + 64 : offset - 448, f, missing);
    visit(j > 0 ? kFaceCount : kFaceYm, j > 0 ? offset - 8 : offset + 56, f, missing);
    visit(j < 7 ? kFaceCount : kFaceYp, j < 7 ? offset + 8 : offset - 56, f, missing);
    visit(k > 0 ? kFaceCount : kFaceZm, k > 0 ? offset - 1 : offset + 7, f, missing);
    visit(k < 7 ? kFaceCount : kFaceZp, k < 7 ? offset + 1 : offset - 7, f, missing);
  }

 private:
  template <typename F, typename M>
  void visit(int which, unsigned offset, F& f, M& missing) const {
    if (mRecord[which]) f(*mRecord[which], mValues[which], offset);
    else missing();
  }
  const LeafRecord* mRecord[kFaceCount + 1];
  float* mValues[kFaceCount + 1];
};

/// Value of a voxel entering a layer next to `inner` voxels (section 5, step 3):
/// the nearest inner neighbour's value plus one voxel outside, minus one voxel
/// inside (the minimum outside and the maximum inside in OpenVDB's sign).
template <typename InnerMask>
float valueFromInnerNeighbours(const FaceNeighbours& neighbours, unsigned offset, bool inside, float dx,
                               InnerMask inner) {
  float nearest = std::numeric_limits<float>::max();  // distance from the front, growing outward
  neighbours.forEachNeighbour(
      offset,
      [&](const LeafRecord& r, const float* values, unsigned o) {
        if (inner(r).isOn(o)) nearest = std::min(nearest, inside ? -values[o] : values[o]);
      },
      [] {});
  return inside ? -(nearest + dx) : nearest + dx;
}

/// Creates the leaves that the next layer grows into and links their records.
void allocateRequestedLeaves(SparseFieldState& state) {
  static constexpr int kStep[kFaceCount][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0},
                                               {0, 1, 0},  {0, 0, -1}, {0, 0, 1}};
  LeafTable& table = state.table;
  std::vector<openvdb::Coord> origins;
  const int dim = static_cast<int>(FloatLeaf::DIM);
  for (std::size_t r = 0; r < table.size(); ++r) {
    LeafRecord& record = table[r];
    if (!record.live() || record.faceRequest == 0) continue;
    for (int f = 0; f < kFaceCount; ++f)
      if (record.faceRequest & (1u << f))
        origins.push_back(record.origin.offsetBy(kStep[f][0] * dim, kStep[f][1] * dim, kStep[f][2] * dim));
    record.faceRequest = 0;
  }
  std::sort(origins.begin(), origins.end());
  origins.erase(std::unique(origins.begin(), origins.end()), origins.end());
  for (const openvdb::Coord& origin : origins) {
    if (table.find(origin) >= 0) continue;
    // A new leaf takes the value of the inactive tile it replaces: +-background.
    table.add(state.tree().touchLeaf(origin));
  }
}

}  // namespace

std::size_t indexActivePoints(SparseFieldState& state) {
  std::size_t total = 0;
  for (std::size_t r = 0; r < state.table.size(); ++r) {
    LeafRecord& record = state.table[r];
    if (!record.live()) continue;
    record.firstActive = static_cast<std::uint32_t>(total);
    total += record.layer[0].countOn();
  }
  state.pointValues.resize(total);
  return total;
}

double chooseTimeStep(const SparseFieldState& state, double maxSpeed, double curvatureWeight, double maxDt) {
  double dt = maxDt;
  // Eqs. 31-32: the fastest front over the active set may move maxStepChange voxels.
  if (maxSpeed > 0.0) dt = std::min(dt, state.options.maxStepChange * state.dx / maxSpeed);
  // Stability of the explicit curvature term (Eq. 26).
  if (curvatureWeight > 0.0)
    dt = std::min(dt, state.options.curvatureStepLimit * state.dx * state.dx / curvatureWeight);
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
    std::uint32_t points = 0, out = 0, in = 0, conflicts = 0, active = 0;
  };
  std::vector<LeafTally> tally(table.size());

  // Step 2: add the change to every active point; points leaving [-1/2, 1/2]
  // voxel become candidates to move out (up) or in (down).
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    record.up.setOff();
    record.down.setOff();
    record.conflict.setOff();
    float* values = record.leaf->buffer().data();
    LeafTally& t = tally[r];
    std::uint32_t slot = record.firstActive;
    forEachOn(record.layer[0], [&](unsigned o) {
      const float change = fdt * rates[slot++];
      const float v = values[o] + change;
      values[o] = v;
      t.sumSq += static_cast<double>(change) * change;
      t.maxChange = std::max(t.maxChange, std::fabs(change));
      ++t.points;
      if (v > half) record.up.setOn(o);
      else if (v < -half) record.down.setOn(o);
    });
  });

  // Two adjacent points leaving on opposite sides would leave a sign change
  // without an active point between them (Appendix, Proposition 1 needs the
  // moves to be separate). Both stay active, held at the edge of the range.
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    if (!anyOn(record.up) && !anyOn(record.down)) return;
    FaceNeighbours neighbours(table, record);
    const LeafMask* ups[kFaceCount];
    const LeafMask* downs[kFaceCount];
    neighbours.masks(&LeafRecord::up, ups);
    neighbours.masks(&LeafRecord::down, downs);
    LeafMask conflict = record.up & dilateFaces(record.down, downs);
    conflict |= record.down & dilateFaces(record.up, ups);
    if (!anyOn(conflict)) return;
    float* values = record.leaf->buffer().data();
    forEachOn(conflict, [&](unsigned o) { values[o] = record.up.isOn(o) ? half : -half; });
    record.conflict = conflict;
    tally[r].conflicts = conflict.countOn();
  });

  // Step 4 for the active set: points that leave are replaced by their
  // neighbours across the zero crossing (the movement of Eq. 42), whose values
  // come from the active points next to them (step 3).
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    FaceNeighbours neighbours(table, record);
    const LeafMask leavingOut = minus(record.up, record.conflict);
    const LeafMask leavingIn = minus(record.down, record.conflict);
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

    record.next = minus(minus(record.layer[0], leavingOut), leavingIn);
    tally[r].out = leavingOut.countOn();
    tally[r].in = leavingIn.countOn();
    if (!anyOn(candidates)) return;
    float* values = record.leaf->buffer().data();
    const auto oldActive = [](const LeafRecord& n) -> const LeafMask& { return n.layer[0]; };
    forEachOn(candidates, [&](unsigned o) {
      const bool inside = values[o] < 0.0f;
      if (inside ? !besideOut.isOn(o) : !besideIn.isOn(o)) return;
      values[o] = valueFromInnerNeighbours(neighbours, o, inside, dx, oldActive);
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
  for (std::size_t r = 0; r < table.size(); ++r)
    if (table[r].live()) result.activeVoxels += table[r].layer[0].countOn();
  return result;
}

void rebuildLayers(SparseFieldState& state) {
  LeafTable& table = state.table;
  const std::size_t grain = state.options.grainSize;
  const int layers = state.options.layers;
  const float dx = static_cast<float>(state.dx);

  // Step 3: layer i is every voxel next to layer i-1 that is in no inner layer,
  // valued from its nearest neighbour in layer i-1. Points of the old layers
  // with no inner neighbour fall outward or out of the layers (step 4).
  for (int i = 1; i <= layers; ++i) {
    if (i == layers) allocateRequestedLeaves(state);
    forEachRecord(table, grain, [&](std::size_t r) {
      LeafRecord& record = table[r];
      FaceNeighbours neighbours(table, record);
      const LeafMask* inner[kFaceCount];
      if (i == 1) neighbours.masks(&LeafRecord::next, inner);
      else {
        for (int f = 0; f < kFaceCount; ++f) {
          const std::int32_t n = record.neighbour[kFaceSlot[f]];
          inner[f] = n >= 0 ? &table[n].layer[i - 1] : nullptr;
        }
      }
      const LeafMask& innerSelf = i == 1 ? record.next : record.layer[i - 1];
      LeafMask ring = dilateFaces(innerSelf, inner);
      ring -= record.next;
      for (int j = 1; j < i; ++j) ring -= record.layer[j];
      record.layer[i] = ring;

      float* values = record.leaf->buffer().data();
      const auto innerOf = [i](const LeafRecord& n) -> const LeafMask& {
        return i == 1 ? n.next : n.layer[i - 1];
      };
      forEachOn(ring, [&](unsigned o) {
        values[o] = valueFromInnerNeighbours(neighbours, o, values[o] < 0.0f, dx, innerOf);
      });
      if (i == layers - 1) {
        // The outermost layer grows one voxel past this one: ask for the leaves it reaches.
        std::uint8_t request = 0;
        for (int f = 0; f < kFaceCount; ++f)
          if (record.neighbour[kFaceSlot[f]] < 0 && touchesFace(ring, f)) request |= std::uint8_t(1u << f);
        record.faceRequest = request;
      }
    });
  }

  // Commit: the layers become the band (the value tree's active voxels); voxels
  // that left every layer take the background value of their side.
  const float background = state.background;
  std::vector<std::uint8_t> empty(table.size(), 0);
  forEachRecord(table, grain, [&](std::size_t r) {
    LeafRecord& record = table[r];
    LeafMask band = record.next;
    for (int i = 1; i <= layers; ++i) band |= record.layer[i];
    const LeafMask retired = minus(record.leaf->getValueMask(), band);
    float* values = record.leaf->buffer().data();
    forEachOn(retired, [&](unsigned o) { values[o] = values[o] < 0.0f ? -background : background; });
    record.leaf->setValueMask(band);
    record.layer[0] = record.next;
    empty[r] = !anyOn(band);
  });

  // A leaf left without layers lies wholly on one side of the surface: it
  // becomes an inactive tile of that side.
  for (std::size_t r = 0; r < table.size(); ++r) {
    if (!empty[r] || !table[r].live()) continue;
    const LeafRecord& record = table[r];
    const float value = record.leaf->buffer().data()[0] < 0.0f ? -background : background;
    const openvdb::Coord origin = record.origin;
    table.remove(static_cast<std::int32_t>(r));
    state.tree().addTile(1, origin, value, false);
  }
}

}  // namespace levelfuse::detail

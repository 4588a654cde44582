// levelfuse: the scans of a team read by the processes that need them.

#include <levelfuse/recon/TeamScans.h>

#include <levelfuse/scan/AccumulationCost.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>

namespace levelfuse {

namespace {

/// `values` as bytes, and back.
template <typename T>
PackedLeaves bytesOf(const std::vector<T>& values) {
  PackedLeaves bytes;
  detail::appendBytes(bytes, values.data(), values.size() * sizeof(T));
  return bytes;
}

template <typename T>
std::vector<T> valuesOf(const PackedLeaves& bytes, const char* what) {
  if (bytes.size() % sizeof(T) != 0)
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(bytes.size()) +
                                " bytes are no whole number of values");
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

/// What a process tells every other before the cut: whether it needs every
/// scan, then the boxes of its reached leaf nodes (leaf units), six numbers each.
PackedLeaves packReached(const ReachedLeaves& reached, bool needsEvery) {
  std::vector<openvdb::Int32> numbers{needsEvery ? 1 : 0};
  for (auto on = reached.leaves().cbeginValueOn(); on; ++on) {
    const openvdb::CoordBBox box = on.getBoundingBox();  // a leaf, or a tile of them
    for (int axis = 0; axis < 3; ++axis) numbers.push_back(box.min()[axis]);
    for (int axis = 0; axis < 3; ++axis) numbers.push_back(box.max()[axis]);
  }
  return bytesOf(numbers);
}

/// Adds a process's reached leaves (packReached) to `whole`; returns whether it needs every scan.
bool addReached(const PackedLeaves& packed, ReachedLeaves& whole) {
  const std::vector<openvdb::Int32> numbers = valuesOf<openvdb::Int32>(packed, "planTeamScans");
  if (numbers.empty() || (numbers.size() - 1) % 6 != 0)
    throw std::invalid_argument("planTeamScans: " + std::to_string(numbers.size()) +
                                " numbers are no process's reached leaves");
  for (std::size_t at = 1; at < numbers.size(); at += 6) {
    const openvdb::CoordBBox box(openvdb::Coord(numbers[at], numbers[at + 1], numbers[at + 2]),
                                 openvdb::Coord(numbers[at + 3], numbers[at + 4], numbers[at + 5]));
    whole.add(box);
  }
  return numbers[0] != 0;
}

/// Whether a map whose windows reach the columns of `span` reaches the slab
/// of the data `data`: a column of leaf nodes of slack on each side.
bool reachesSlab(const ReachedLeaves::Span& span, const SlabBounds& data) {
  if (span.empty()) return false;
  const std::int64_t slack = kLeafNodeWidth;
  const std::int64_t begin = data.hasLower() ? std::int64_t{data.begin} - slack : INT64_MIN;
  const std::int64_t end = data.hasHigher() ? std::int64_t{data.end} + slack : INT64_MAX;
  return std::int64_t{span.last} >= begin && std::int64_t{span.first} < end;
}

}  // namespace

ScanSummary teamSummary(const ScanSummary& own, const SlabTeam& team) {
  std::vector<PackedLeaves> toEach(static_cast<std::size_t>(team.size()), bytesOf(own.numbers()));
  ScanSummary whole;
  for (const PackedLeaves& packed : team.exchange(std::move(toEach)))
    whole.add(ScanSummary::fromNumbers(valuesOf<double>(packed, "teamSummary")));
  return whole;
}

openvdb::BBoxd carvingBoxOf(const SlabBounds& data, const openvdb::CoordBBox& dataVoxels, double voxelSize) {
  // Carving decides the blocks of the data's box within the slab of the data
  // and one block beyond (linearSolutionSlabField): two blocks here.
  const std::int64_t block = kLeafNodeWidth;
  openvdb::Vec3d lo = dataVoxels.min().asVec3d(), hi = dataVoxels.max().asVec3d();
  if (data.hasLower()) lo.x() = std::max<double>(lo.x(), static_cast<double>(std::int64_t{data.begin} - 2 * block));
  if (data.hasHigher()) hi.x() = std::min<double>(hi.x(), static_cast<double>(std::int64_t{data.end} + 2 * block));
  const openvdb::Vec3d grow(static_cast<double>(block) + 0.5);
  return openvdb::BBoxd((lo - grow) * voxelSize, (hi + grow) * voxelSize);
}

TeamScanPlan planTeamScans(const PackedScans& held, const std::vector<std::size_t>& numbers, std::size_t scanCount,
                           const ReconstructionSettings& settings, bool needsEvery, const SlabTeam& team,
                           const Interrupter& interrupter) {
  if (numbers.size() != held.maps.size())
    throw std::invalid_argument("planTeamScans: " + std::to_string(held.maps.size()) + " scans held but " +
                                std::to_string(numbers.size()) + " numbered");
  TeamScanPlan plan;
  if (!sharesDataInSlabs(settings, &team)) {
    for (std::size_t scan = 0; scan < scanCount; ++scan) plan.needed.push_back(scan);
    return plan;
  }
  // Where the windows of the scans held reach, every process's together.
  ReachedLeaves reached = reachedLeavesOf(settings);
  std::vector<ReachedLeaves::Span> spans;
  held.unpacked()([&](const RangeMap& map) {
    checkInterrupter(interrupter);
    spans.push_back(reached.add(map));
  });
  ReachedLeaves whole = reachedLeavesOf(settings);
  std::vector<bool> needsEveryScan;
  {
    std::vector<PackedLeaves> toEach(static_cast<std::size_t>(team.size()), packReached(reached, needsEvery));
    for (const PackedLeaves& packed : team.exchange(std::move(toEach))) needsEveryScan.push_back(addReached(packed, whole));
  }
  // Every process's slab, and which of the scans held each needs.
  const std::vector<SharedDataSlab> slabs = sharedDataSlabs(whole, team.size());
  const openvdb::CoordBBox dataVoxels = whole.voxelBox();
  const double voxelSize = settings.voxelSize;  // of the one grid
  std::vector<PackedLeaves> toEach(slabs.size());
  for (std::size_t process = 0; process < slabs.size(); ++process) {
    const SlabBounds& data = slabs[process].data;
    const openvdb::BBoxd carved = carvingBoxOf(data, dataVoxels, voxelSize);
    std::vector<std::uint64_t> neededThere;
    for (std::size_t i = 0; i < held.maps.size(); ++i)
      if (needsEveryScan[process] || reachesSlab(spans[i], data) || held.maps[i].shell().mayBeSeenIn(carved))
        neededThere.push_back(numbers[i]);
    toEach[process] = bytesOf(neededThere);
  }
  for (const PackedLeaves& packed : team.exchange(std::move(toEach)))
    for (std::uint64_t scan : valuesOf<std::uint64_t>(packed, "planTeamScans")) plan.needed.push_back(scan);
  std::sort(plan.needed.begin(), plan.needed.end());
  plan.slab = slabs.at(static_cast<std::size_t>(team.rank()));
  return plan;
}

namespace {

/// Scans held, each with its number among all the inputs' scans.
using ScansByNumber = std::vector<std::pair<std::size_t, PackedRangeMap>>;

/// Moves the scans of `part` that `isNeeded` picks into `into`; the others are let go.
void moveScansNeeded(NumberedScans& part, const std::function<bool(std::size_t)>& isNeeded, ScansByNumber& into) {
  for (std::size_t i = 0; i < part.numbers.size(); ++i)
    if (isNeeded(part.numbers[i])) into.emplace_back(part.numbers[i], std::move(part.scans.maps[i]));
  part.scans = PackedScans();
}

/// `scans` in the order of their numbers, with the summary of all the inputs' scans `whole`.
PackedScans inNumberOrder(ScansByNumber scans, const ScanSummary& whole, std::vector<std::size_t>& numbers) {
  std::stable_sort(scans.begin(), scans.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  PackedScans ordered;
  ordered.summary = whole;
  for (auto& [number, map] : scans) {
    numbers.push_back(number);
    ordered.maps.push_back(std::move(map));
  }
  return ordered;
}

}  // namespace

TeamShare readTeamScans(const NumberedScanReader& read, const ReconstructionOptions& given, bool needsEvery,
                        const SlabTeam& team, const Interrupter& interrupter) {
  NumberedScans first = read([&](std::size_t scan) { return readFirstBy(scan, team.rank(), team.size()); });
  const ScanSummary whole = teamSummary(first.scans.summary, team);
  TeamShare share;
  share.settings = resolveReconstructionSettings(given, whole);
  const TeamScanPlan plan =
      planTeamScans(first.scans, first.numbers, first.scanCount, share.settings, needsEvery, team, interrupter);
  share.slab = plan.slab;
  const auto isNeeded = [&](std::size_t scan) {
    return std::binary_search(plan.needed.begin(), plan.needed.end(), scan);
  };
  // Those read first that this process does not need go before it reads those it lacks.
  ScansByNumber needed;
  moveScansNeeded(first, isNeeded, needed);
  NumberedScans rest = read([&](std::size_t scan) {
    return isNeeded(scan) && !std::binary_search(first.numbers.begin(), first.numbers.end(), scan);
  });
  moveScansNeeded(rest, isNeeded, needed);
  NumberedScans& held = share.held;
  held.scans = inNumberOrder(std::move(needed), whole, held.numbers);
  if (!needsEvery) held.scans.letSamplesGo();
  held.scanCount = first.scanCount;
  held.firstScan = std::move(first.firstScan);  // scan 0, which the first process reads first
  return share;
}

}  // namespace levelfuse

// levelfuse reconstruct: range scans in, a level set, a mesh and a picture out.

#include "Cancellation.h"
#include "Commands.h"
#include "Job.h"
#include "ProgressBar.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/Manifest.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/MeshFile.h>
#include <levelfuse/io/Preview.h>
#include <levelfuse/io/Scans.h>
#include <levelfuse/io/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/recon/TeamScans.h>
#include <levelfuse/scan/PackedRangeMap.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <deque>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse::cli {
namespace {

struct ReconstructSettings {
  std::vector<std::string> inputs;
  std::string output, mesh, preview;
  ReconstructionOptions options;
  bool linear = false;
  std::string towardScanner;
  double sigma = 0.0;
  double depthScale = 0.0;  // the convention's
  double maxDepth = 0.0;    // none
  int frameStride = 1;
  std::string view, up;
  std::optional<bool> trimUnseen;  // none: for scenes (depth frames) only
  int threads = 0;
  double maxMemoryGiB = 0.0;
  bool json = false, quiet = false;
  bool pieces = false;    ///< each rank writes its piece of the level set
  std::string piecesOf;  ///< with pieces, -o as given: output is this rank's piece's file
};

/// The file of one rank's piece: `output` with ".<rank>-of-<ranks>" before its extension (.vdb if none).
std::string pieceFileName(const std::string& output, int rank, int ranks) {
  std::filesystem::path path(output);
  const std::string extension = path.has_extension() ? path.extension().string() : ".vdb";
  path.replace_extension();
  return path.string() + "." + std::to_string(rank) + "-of-" + std::to_string(ranks) + extension;
}

/// What --pieces cannot go with, and the rank's own file name in place of -o's.
void checkPiecesSettings(ReconstructSettings& s) {
  if (s.output.empty()) throw std::invalid_argument("--pieces writes the level set in pieces: give -o result.vdb");
  if (!s.mesh.empty() || !s.preview.empty())
    throw std::invalid_argument(
        "--pieces keeps the level set in pieces, one per rank, and a mesh or preview needs it whole: leave out "
        "--mesh and --preview, or --pieces");
  if (s.linear)
    throw std::invalid_argument("--pieces shares the evolution's output between the ranks; --linear has no evolution");
  s.piecesOf = s.output;
  s.output = pieceFileName(s.output, jobRank(), jobRanks());
  s.options.keepPieces = true;
}

/// Every option and output, checked before the work starts and before anything is written.
void checkSettings(ReconstructSettings& s) {
  // The budget of the readers and of the reconstruction.
  if (s.maxMemoryGiB > 0.0) io::setMemoryBudget(static_cast<std::uint64_t>(s.maxMemoryGiB * 1073741824.0));
  if (s.output.empty() && s.mesh.empty() && s.preview.empty())
    throw std::invalid_argument("nothing to write: give -o result.vdb, --mesh result.ply or --preview result.png");
  if (s.pieces) checkPiecesSettings(s);
  requireOutputs({s.output, s.mesh, s.preview}, s.inputs);
  if (!s.mesh.empty()) io::requireMeshFileName(s.mesh);
  s.options.minIterations = std::min(s.options.minIterations, s.options.maxIterations);
}

/// What the data and the options cannot give (a window wider than the data, a
/// grid that would not fit) is said of the inputs.
std::runtime_error ofTheInputs(const ReconstructSettings& s, const std::exception& e) {
  return std::runtime_error(joined(s.inputs) + ": " + e.what());
}

/// Every rank's piece file (--pieces), in rank order.
std::vector<std::string> pieceFiles(const ReconstructSettings& s) {
  std::vector<std::string> pieces;
  for (int rank = 0; rank < jobRanks(); ++rank) pieces.push_back(pieceFileName(s.piecesOf, rank, jobRanks()));
  return pieces;
}

/// Every file the job writes: with --pieces, every rank's piece.
std::vector<std::string> jobOutputs(const ReconstructSettings& s) {
  if (!s.pieces) return {s.output, s.mesh, s.preview};
  return pieceFiles(s);
}

/// The scans of the inputs this process holds, and the truth a synthetic manifest records.
struct Inputs {
  PackedScans scans;                  ///< read one at a time and held packed
  std::vector<std::size_t> numbers;   ///< of each scan held, its number among all the inputs' (from 0)
  std::size_t scanCount = 0;          ///< the scans of all the inputs, read or not
  std::optional<RangeMap> firstScan;  ///< a scene's preview looks from its camera
  std::optional<shapes::AnalyticShape> truth;
};

/// Reads the scans of the inputs that `wanted` picks by their number among
/// all the inputs' scans (from 0, in order), every scan if it is not given.
Inputs loadInputs(const ReconstructSettings& s, ProgressBar& bar, const std::function<bool(std::size_t)>& wanted = {}) {
  enterPhase("loading");
  io::ScanLoadOptions load;
  if (!s.towardScanner.empty()) load.stanford.towardScanner = parseVec3(s.towardScanner);
  if (s.sigma > 0.0) load.setSigma(s.sigma);
  load.depthScale = s.depthScale;
  if (s.maxDepth > 0.0) load.maxDepth = s.maxDepth;
  load.frameStride = s.frameStride;
  load.interrupter = cancellationInterrupter();
  load.progress = [&](std::size_t read, std::size_t total) { bar.loading(read, total); };
  Inputs in;
  // Each input numbers its scans from 0, asking for every one in order; the
  // scans wanted are then handed over in order.
  std::size_t asked = 0;
  std::deque<std::size_t> coming;
  load.wanted = [&](std::size_t scan) {
    asked = std::max(asked, scan + 1);
    const std::size_t number = in.scanCount + scan;
    if (wanted && !wanted(number)) return false;
    coming.push_back(number);
    return true;
  };
  load.take = [&](RangeMap&& map) {
    if (!in.firstScan && coming.front() == 0) in.firstScan = map;
    in.numbers.push_back(coming.front());
    coming.pop_front();
    in.scans.add(std::move(map));
  };
  for (const std::string& input : s.inputs) {
    io::loadScans(input, load);
    in.scanCount += asked;
    asked = 0;
    if (std::filesystem::path(input).extension() == ".json" && !in.truth) in.truth = io::loadManifestTruth(input);
  }
  // The scan files the inputs named are inputs too.
  requireOutputs(jobOutputs(s), io::inputsRead());
  return in;
}

/// Scans held, each with its number among all the inputs' scans.
using NumberedScans = std::vector<std::pair<std::size_t, PackedRangeMap>>;

/// Moves the scans of `part` that `isNeeded` picks into `into`; the others are let go.
void moveScansNeeded(Inputs& part, const std::function<bool(std::size_t)>& isNeeded, NumberedScans& into) {
  for (std::size_t i = 0; i < part.numbers.size(); ++i)
    if (isNeeded(part.numbers[i])) into.emplace_back(part.numbers[i], std::move(part.scans.maps[i]));
  part.scans = PackedScans();
}

/// `scans` in the order of their numbers, with the summary of all the inputs' scans `whole`.
PackedScans inNumberOrder(NumberedScans scans, const ScanSummary& whole, std::vector<std::size_t>& numbers) {
  std::stable_sort(scans.begin(), scans.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  PackedScans ordered;
  ordered.summary = whole;
  for (auto& [number, map] : scans) {
    numbers.push_back(number);
    ordered.maps.push_back(std::move(map));
  }
  return ordered;
}

/// The scans of the inputs this rank of an MPI `team` needs: the ranks
/// read the scans in turn, agree on the settings from all of them, and,
/// where they share the data in slabs, each keeps the scans its slab needs
/// and reads those it lacks (recon/TeamScans.h). `cut` is set to this
/// rank's slab of the data where they share it.
Inputs loadTeamInputs(const ReconstructSettings& s, ProgressBar& bar, const SlabTeam& team,
                      std::optional<SharedDataSlab>& cut) {
  Inputs first = loadInputs(s, bar, [&](std::size_t scan) { return readFirstBy(scan, team.rank(), team.size()); });
  const ScanSummary whole = teamSummary(first.scans.summary, team);
  // The rank that measures and writes the whole surface needs every scan for the fit and the colour.
  const bool measuresTheSurface = leadsTheJob() && !s.pieces;
  const TeamScanPlan plan = [&] {
    try {
      return planTeamScans(first.scans, first.numbers, first.scanCount, resolveReconstructionOptions(s.options, whole),
                           measuresTheSurface, team, cancellationInterrupter());
    } catch (const std::invalid_argument& e) {
      throw ofTheInputs(s, e);
    }
  }();
  cut = plan.slab;
  const auto isNeeded = [&](std::size_t scan) {
    return std::binary_search(plan.needed.begin(), plan.needed.end(), scan);
  };
  // Those read first that this rank does not need go before it reads those it lacks.
  NumberedScans needed;
  moveScansNeeded(first, isNeeded, needed);
  Inputs rest = loadInputs(s, bar, [&](std::size_t scan) {
    return isNeeded(scan) && !std::binary_search(first.numbers.begin(), first.numbers.end(), scan);
  });
  moveScansNeeded(rest, isNeeded, needed);
  Inputs in;
  in.scans = inNumberOrder(std::move(needed), whole, in.numbers);
  // Only the fit reads the points the scanners measured.
  if (!measuresTheSurface) in.scans.letSamplesGo();
  in.scanCount = first.scanCount;
  in.truth = std::move(first.truth);
  in.firstScan = std::move(first.firstScan);  // scan 0, which the first rank reads first
  return in;
}

ScansReconstruction prepare(Inputs& in, const ReconstructSettings& s, ProgressBar& bar, const SharedDataSlab* cut) {
  try {
    if (resolveReconstructionOptions(s.options, in.scans.summary).dataTerm == DataTermSource::kGrids)
      enterPhase("integrating");
    // Under mpirun the ranks share the evolution, and each may integrate its slab of the data alone.
    return prepareReconstruction(
        std::move(in.scans), s.options, [&](std::size_t done, std::size_t total) { bar.integrating(done, total); },
        cancellationInterrupter(), s.linear ? nullptr : jobTeam(), cut);
  } catch (const std::invalid_argument& e) {
    throw ofTheInputs(s, e);
  } catch (const InsufficientMemory& e) {
    throw ofTheInputs(s, e);
  }
}

/// How the outputs show the surface: scans of a scene (depth frames) are seen
/// from their first camera, and what no scan observed is left out of the mesh
/// and preview (trimmed) for scenes, unless the options say otherwise.
struct Presentation {
  bool scene = false;
  bool trim = false;
};

Presentation presentationOf(const Reconstructor& reconstructor, const ReconstructSettings& s) {
  const bool scene = reconstructor.summary().aScene();
  return {scene, trimsUnseen(scene, s.trimUnseen)};
}

/// The surface, evolved or (--linear) the linear solution, with its weight
/// grid where an output needs it, and the run's metadata.
ReconstructionResult reconstructSurface(const Reconstructor& reconstructor, const ReconstructSettings& s,
                                        const Presentation& shown, ProgressBar& bar) {
  ReconstructionResult result;
  try {
    if (s.linear) {
      enterPhase("solving");
      result.levelSet = reconstructor.linearSolution(cancellationInterrupter());
    } else {
      enterPhase("evolving");
      result = reconstructor.run(
          [&](const ReconstructionProgress& p) {
            bar.update(p);
            return !cancellationRequested();
          },
          cancellationInterrupter(), jobTeam());
    }
  } catch (const InsufficientMemory& e) {
    throw ofTheInputs(s, e);
  }
  if (!result.levelSet) return result;  // another rank of the job holds the surface
  bar.finish();
  enterPhase("measuring");
  openvdb::FloatGrid& surface = *result.levelSet;
  if (!result.weight && (shown.trim || !s.output.empty()))
    result.weight = reconstructor.surfaceWeight(surface, cancellationInterrupter());
  if (s.linear) result.colour = reconstructor.surfaceColour(surface, cancellationInterrupter());
  describeInputs(surface, s.inputs, s.linear, shown.scene);
  return result;
}

/// What the summary says of the scans and of the surface.
struct Measures {
  std::size_t readings = 0, points = 0;
  int fitSample = 1;  ///< one reading in fitSample along each row and column
  std::optional<DataFit> fit;  ///< none when the surface is in pieces (--pieces)
  double truthRms = -1.0;
};

/// The scans' counts alone.
Measures countsOf(const ScansReconstruction& r) {
  Measures m;
  m.readings = r.reconstructor->summary().readings();
  m.points = r.reconstructor->summary().points();
  return m;
}

/// The counts, the surface's fit to the scans and, for synthetic scans, its error.
Measures measure(const ScansReconstruction& r, const ReconstructionResult& result, const Presentation& shown,
                 const Inputs& in) {
  const openvdb::FloatGrid& surface = *result.levelSet;
  Measures m = countsOf(r);
  m.fitSample = fitStride(r.scans, kFitPointsAtMost);
  m.fit = measureDataFit(surface, r.scans, m.fitSample);
  if (in.truth) m.truthRms = rmsOver(zeroCrossingsShown(surface, shown.trim ? result.weight.get() : nullptr), *in.truth);
  return m;
}

/// The grids of the .vdb output: the level set, its weight and, where the
/// scans carry colour, its colour.
openvdb::GridCPtrVec gridsWritten(const ReconstructionResult& result) {
  openvdb::GridCPtrVec grids{result.levelSet, result.weight};
  if (result.colour) grids.push_back(result.colour);
  return grids;
}

/// Writes the .vdb output (the level set, its weight and colour) into `outputs`.
void writeGrids(io::OutputSet& outputs, const ReconstructionResult& result, const ReconstructSettings& s) {
  if (s.output.empty()) return;
  enterPhase("writing");
  io::writeVdb(outputs, s.output, gridsWritten(result));
}

/// Writes the mesh and the preview into `outputs`, then commits them all
/// together; returns the mesh's triangles.
std::size_t writeShownOutputs(io::OutputSet& outputs, const Inputs& in, const ReconstructionResult& result,
                              const Presentation& shown, const ReconstructSettings& s) {
  const openvdb::FloatGrid& surface = *result.levelSet;
  std::optional<TriangleMesh> mesh;
  if (!s.mesh.empty()) {
    enterPhase("meshing");
    mesh = meshShown(surface, shown.trim ? result.weight.get() : nullptr, 0.0, result.colour.get());
  }
  io::PreviewOptions preview;
  if (!s.view.empty()) preview.toward = parseVec3(s.view);
  if (!s.up.empty()) preview.up = parseVec3(s.up);
  // A scene is seen from where its first frame's camera stood, unless a view is asked for.
  const bool fromItsCamera = shown.scene && s.view.empty();
  preview = previewShown(preview, fromItsCamera ? &*in.firstScan : nullptr,
                         shown.trim ? result.weight : nullptr);
  preview.colour = result.colour;
  enterPhase("writing");
  if (mesh) io::writeMesh(outputs, s.mesh, *mesh);
  if (!s.preview.empty()) io::writePreviewPng(outputs, surface, s.preview, preview);
  commitOutputs(outputs);
  return mesh ? mesh->triangleCount() : 0;
}

/// The summary of a run, as JSON (lengths in metres) or as text for a person.
struct Summary {
  const ReconstructSettings& settings;
  const Reconstructor& reconstructor;
  const ReconstructionResult& result;
  const Inputs& inputs;
  const Measures& measures;
  bool trimmed = false;  ///< the mesh and preview left out what no scan observed
  std::size_t triangles = 0;
  double seconds = 0.0;
  std::vector<RankFacts> ranks;  ///< in an MPI job, what each rank's share cost
  std::uint64_t bandVoxels = 0;     ///< the level set's active voxels, every piece's
  std::vector<std::string> pieces;  ///< with --pieces, every rank's file
  std::uint64_t dataTermBytes = 0;  ///< this process's grids of the data term (0 from the maps)
};

/// The memory of the grids of the data term `made` holds, with the largest
/// grid this rank integrated within its slab as `result` was made, one at a
/// time (0 with the data term from the maps).
std::uint64_t dataTermBytesOf(const ScansReconstruction& made, const ReconstructionResult& result) {
  if (!made.fusion) return 0;
  std::uint64_t slabGrid = 0;
  for (const LevelReport& level : result.levels) slabGrid = std::max<std::uint64_t>(slabGrid, level.slabDataTermBytes);
  return made.fusion->dataTermBytes() + slabGrid;
}

/// The run's phases as the command entered them, the reconstruction's own in
/// place of the one that ran it ("evolving").
std::vector<PhaseTime> runPhases(const ReconstructionResult& result) {
  std::vector<PhaseTime> phases;
  for (const PhaseTime& phase : phaseTimes()) {
    if (phase.name == "evolving" && !result.phases.empty())
      phases.insert(phases.end(), result.phases.begin(), result.phases.end());
    else
      phases.push_back(phase);
  }
  return phases;
}

nlohmann::json phasesJson(const ReconstructionResult& result) {
  nlohmann::json phases = nlohmann::json::array();
  for (const PhaseTime& p : runPhases(result))
    phases.push_back({{"name", p.name}, {"seconds", p.seconds}, {"cpu_seconds", p.cpuSeconds}});
  return phases;
}

/// JSON of the fit to the points, null if it was not measured.
nlohmann::json fitJson(const std::optional<DataFit>& fit) {
  if (!fit) return nullptr;
  return {{"points", fit->readings}, {"mean", fit->mean},     {"rms", fit->rms},
          {"median", fit->median},  {"p90", fit->p90},       {"p99", fit->p99},
          {"within_voxel", fit->withinVoxel}, {"beyond_band", fit->beyondBand}};
}

void printJson(const Summary& r) {
  const ReconstructSettings& s = r.settings;
  const ReconstructionOptions& o = r.reconstructor.options();
  nlohmann::json levels = nlohmann::json::array();
  for (const LevelReport& l : r.result.levels)
    levels.push_back({{"voxel_size", l.voxelSize},
                      {"iterations", l.iterations},
                      {"converged", l.converged},
                      {"settled", l.settled},
                      {"simulated_time", l.simulatedTime},
                      {"seconds", l.seconds},
                      {"active_set_voxels", l.activeSetVoxels},
                      {"band_voxels", l.bandVoxels},
                      {"engine_bytes", l.engineBytes}});
  nlohmann::json j{{"inputs", s.inputs},
                   {"scans", r.reconstructor.summary().scans()},
                   {"points", r.measures.points},
                   {"readings", r.measures.readings},
                   {"method", s.linear ? "linear" : "evolution"},
                   {"voxel_size", *o.voxelSize},
                   {"levels", *o.levels},
                   {"beta", *o.beta},
                   {"epsilon", *o.epsilon},
                   {"grids", levels},
                   {"narrow_band_voxels", r.bandVoxels},
                   {"peak_engine_bytes", r.result.peakEngineBytes},
                   {"data_term_bytes", r.dataTermBytes},
                   {"peak_memory_bytes", peakResidentBytes()},
                   {"fit", fitJson(r.measures.fit)},
                   {"seconds", r.seconds},
                   {"cpu_seconds", processCpuSeconds()},
                   {"phases", phasesJson(r.result)},
                   {"outputs", {{"vdb", r.pieces.empty() ? nlohmann::json(s.output) : nlohmann::json(r.pieces)},
                                {"mesh", s.mesh},
                                {"preview", s.preview}}},
                   {"triangles", r.triangles},
                   {"trimmed_unseen", r.trimmed}};
  if (r.ranks.size() > 1) {
    nlohmann::json ranks = nlohmann::json::array();
    for (const RankFacts& f : r.ranks)
      ranks.push_back({{"seconds", f.seconds},
                       {"peak_memory_bytes", f.peakBytes},
                       {"peak_engine_bytes", f.engineBytes},
                       {"leaf_nodes", f.leafNodes},
                       {"ghost_bytes_sent", f.ghostBytes},
                       {"data_term_bytes", f.dataTermBytes},
                       {"scans_held", f.scansHeld}});
    j["ranks"] = ranks;
  }
  if (r.inputs.truth && r.measures.truthRms >= 0.0)
    j["truth"] = {{"shape", r.inputs.truth->name()},
                  {"rms_error", r.measures.truthRms},
                  {"measured_on", r.trimmed ? "the surface seen" : "the whole surface"},
                  {"rms_error_voxels", r.measures.truthRms / *o.voxelSize}};
  std::cout << j.dump(2) << "\n";
}

/// The summary's line of the fit to the points.
void printFit(const Measures& m) {
  if (!m.fit) {
    std::cout << "  fit to the points: not measured, the surface is in pieces (--pieces)\n";
    return;
  }
  const DataFit& fit = *m.fit;
  std::cout << "  fit to the points"
            << (m.fitSample > 1 ? " (a sample of " + withCommas(fit.readings) + ": one reading in " +
                                      std::to_string(m.fitSample) + " along each row and column of each scan)"
                                : std::string())
            << ": mean " << length(fit.mean) << ", median " << length(fit.median) << ", 90% " << length(fit.p90)
            << "; " << fixed(100.0 * fit.withinVoxel, 4) << "% within a voxel, " << fixed(100.0 * fit.beyondBand, 3)
            << "% beyond the band\n";
}

/// The summary's line of the time taken: in all, of CPU, and per phase (those
/// of at least a hundredth of a second).
void printTimes(const Summary& r) {
  std::cout << "  " << duration(r.seconds) << " (CPU " << duration(processCpuSeconds()) << ")";
  const char* separator = ": ";
  for (const PhaseTime& phase : runPhases(r.result)) {
    if (phase.seconds < 0.005) continue;
    std::cout << separator << phase.name << " " << duration(phase.seconds);
    separator = ", ";
  }
  std::cout << "\n";
}

/// The summary's lines of the files written.
void printWritten(const Summary& r) {
  const ReconstructSettings& s = r.settings;
  for (const std::string& piece : r.pieces)
    std::cout << "  wrote " << piece << " (a piece of the closed level set, " << r.pieces.size()
              << " in all, and its weight grid)\n";
  for (const std::string* path : {&s.output, &s.mesh, &s.preview})
    if (!path->empty() && r.pieces.empty())
      std::cout << "  wrote " << *path
                << (path == &s.mesh ? " (" + withCommas(r.triangles) + " triangles" +
                                          (r.trimmed ? ", unseen parts left out" : "") + ")"
                    : path == &s.output ? " (the closed level set and its weight grid)"
                                        : "")
                << "\n";
}

void printText(const Summary& r) {
  const ReconstructSettings& s = r.settings;
  const ReconstructionOptions& o = r.reconstructor.options();
  const Measures& m = r.measures;
  std::cout << "levelfuse reconstruct: " << r.reconstructor.summary().scans() << " scans, " << withCommas(m.points)
            << " points"
            << (m.points != m.readings ? " (" + withCommas(m.readings) + " readings of their range maps)"
                                       : std::string())
            << " (" << joined(s.inputs) << ")\n"
            << "  voxel " << length(*o.voxelSize) << ", " << *o.levels << (*o.levels == 1 ? " grid" : " grids")
            << ", beta " << fixed(*o.beta) << " voxels, window " << length(*o.epsilon) << "\n";
  if (s.linear) std::cout << "  the linear solution (zero set of g), no evolution\n";
  for (const LevelReport& l : r.result.levels)
    std::cout << "  grid " << length(l.voxelSize) << ": " << l.iterations << " iterations ("
              << (l.converged ? "converged" : l.settled ? "settled" : "iteration limit") << "), "
              << withCommas(l.activeSetVoxels) << " voxels in the active set, " << fixed(l.seconds, 3) << " s\n";
  std::cout << "  surface: " << withCommas(r.bandVoxels)
            << " narrow-band voxels; memory: engine " << mebibytes(r.result.peakEngineBytes)
            << (r.dataTermBytes > 0 ? ", data term " + mebibytes(r.dataTermBytes) : std::string()) << ", process peak "
            << mebibytes(peakResidentBytes()) << (r.ranks.size() > 1 ? " (rank 0)" : "") << "\n";
  if (r.ranks.size() > 1) {
    std::uint64_t iterations = 0;
    for (const LevelReport& l : r.result.levels) iterations += static_cast<std::uint64_t>(l.iterations);
    iterations = std::max<std::uint64_t>(iterations, 1);
    std::cout << "  " << r.ranks.size() << " MPI ranks, one slab of every grid each:\n";
    for (std::size_t k = 0; k < r.ranks.size(); ++k)
      std::cout << "    rank " << k << ": " << withCommas(r.ranks[k].leafNodes) << " leaf nodes of the finest grid, engine "
                << mebibytes(r.ranks[k].engineBytes)
                << (r.ranks[k].dataTermBytes > 0 ? ", data term " + mebibytes(r.ranks[k].dataTermBytes) : std::string())
                << ", " << withCommas(r.ranks[k].scansHeld) << (r.ranks[k].scansHeld == 1 ? " scan" : " scans")
                << ", process peak " << mebibytes(r.ranks[k].peakBytes) << ", "
                << fixed(r.ranks[k].seconds, 3) << " s to the end of the evolution, "
                << mebibytes(r.ranks[k].ghostBytes) << " of ghosts sent (" << mebibytes(r.ranks[k].ghostBytes / iterations)
                << " an iteration)\n";
  }
  printFit(m);
  if (r.inputs.truth && m.truthRms >= 0.0)
    std::cout << "  error against the true " << r.inputs.truth->name() << (r.trimmed ? " where seen" : "")
              << ": rms " << length(m.truthRms) << " ("
              << fixed(m.truthRms / *o.voxelSize, 3) << " voxel)\n";
  printTimes(r);
  printWritten(r);
}

/// Writes this rank's piece (its level set and weight grid) with every other
/// rank's: all are committed, or, when any rank cannot write its own, none
/// is, every rank's temporary removed before any rank reports why. Every
/// rank learns why the first that failed did, so whichever rank's line the
/// job prints before it ends says it.
void writePieceWithTheOthers(const ReconstructionResult& result, const ReconstructSettings& s) {
  enterPhase("writing");
  io::OutputSet outputs;
  std::exception_ptr failure;
  std::string why;
  try {
    io::writeVdb(outputs, s.output, gridsWritten(result));
    io::refuseOverwritingInputs(outputs.targets(), io::inputsRead());
    checkCancellation();
  } catch (const std::exception& e) {
    failure = std::current_exception();
    why = e.what();
  } catch (...) {
    failure = std::current_exception();
    why = "an unknown failure";
  }
  const std::vector<std::string> whys = everyRanksText(why);
  const auto firstFailed = std::find_if(whys.begin(), whys.end(), [](const std::string& w) { return !w.empty(); });
  if (firstFailed == whys.end()) {
    outputs.commit();
    return;
  }
  outputs.discard();
  totalOverJob(0);  // every rank's temporary is gone before the job ends
  if (failure) std::rethrow_exception(failure);
  throw std::runtime_error("rank " + std::to_string(firstFailed - whys.begin()) + " of " + std::to_string(whys.size()) +
                           " could not write its piece (" + *firstFailed + "); no piece written");
}

/// With --pieces: every rank writes its piece, the first prints the summary.
int finishInPieces(const ReconstructSettings& s, const ScansReconstruction& made, const ReconstructionResult& result,
                   const Inputs& inputs, const std::vector<RankFacts>& ranks, double seconds) {
  const std::uint64_t bandVoxels = totalOverJob(result.levelSet->activeVoxelCount());
  writePieceWithTheOthers(result, s);
  if (!leadsTheJob()) return kExitSuccess;
  const Measures counts = countsOf(made);
  Summary summary{s,       *made.reconstructor, result, inputs, counts, false, 0, seconds,
                  ranks,   bandVoxels,          {},     dataTermBytesOf(made, result)};
  summary.pieces = pieceFiles(s);
  if (s.json) printJson(summary);
  else if (!s.quiet) printText(summary);
  return kExitSuccess;
}

int runReconstruct(ReconstructSettings s) {
  const auto started = std::chrono::steady_clock::now();
  const ThreadLimit threads(s.threads);
  checkSettings(s);
  // In an MPI job every rank reconstructs; the first one alone prints, and
  // measures and writes what the ranks made together.
  ProgressBar bar(!s.quiet && !s.json && leadsTheJob());
  // Under mpirun the ranks read the scans in turn, then each those it needs.
  const SlabTeam* team = s.linear ? nullptr : jobTeam();
  std::optional<SharedDataSlab> cut;
  Inputs inputs = team ? loadTeamInputs(s, bar, *team, cut) : loadInputs(s, bar);
  const std::size_t scansHeld = inputs.scans.maps.size();
  ScansReconstruction made = prepare(inputs, s, bar, cut ? &*cut : nullptr);
  const Reconstructor& reconstructor = *made.reconstructor;
  const Presentation shown = presentationOf(reconstructor, s);
  if (s.linear && !leadsTheJob()) return kExitSuccess;  // the linear solution is not shared
  ReconstructionResult result = reconstructSurface(reconstructor, s, shown, bar);
  const std::uint64_t dataTermBytes = dataTermBytesOf(made, result);
  std::vector<RankFacts> ranks;
  if (!s.linear)
    ranks = gatherRankFacts(RankFacts{std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                                      peakResidentBytes(), result.peakEngineBytes,
                                      result.levels.empty() ? 0 : result.levels.back().ownLeafNodes,
                                      ghostBytesSent(), dataTermBytes, scansHeld});
  const auto secondsSoFar = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
  if (s.pieces) return finishInPieces(s, made, result, inputs, ranks, secondsSoFar());
  if (!leadsTheJob()) return kExitSuccess;
  made.letTheGridsGo();
  // The grids are written first: past them, only trimming reads the weight,
  // and the fit and the mesh each need memory of the surface's size.
  io::OutputSet outputs;
  writeGrids(outputs, result, s);
  if (!shown.trim) result.weight.reset();
  // The fit is measured for the summary alone: with --quiet nobody reads it.
  const bool summaryShown = s.json || !s.quiet;
  if (summaryShown) enterPhase("measuring");
  const Measures measures = summaryShown ? measure(made, result, shown, inputs) : countsOf(made);
  const std::size_t triangles = writeShownOutputs(outputs, inputs, result, shown, s);
  const Summary summary{s,         reconstructor,  result, inputs, measures, shown.trim,
                        triangles, secondsSoFar(), ranks,  result.levelSet->activeVoxelCount(), {},
                        dataTermBytes};
  if (s.json) printJson(summary);
  else if (summaryShown) printText(summary);
  return kExitSuccess;
}

/// reconstruct's inputs and outputs.
void addReconstructInputsAndOutputs(CLI::App* cmd, const std::shared_ptr<ReconstructSettings>& s) {
  cmd->add_option("inputs", s->inputs,
                  "Scans: a Stanford .conf file, a PTX or E57 file, a JSON manifest, or a folder of depth frames (7-Scenes "
                  "or TUM RGB-D layout)")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("-o,--output", s->output, "Write the surface as an OpenVDB level set (.vdb)");
  cmd->add_option("--mesh", s->mesh, "Write the surface as a triangle mesh (.ply or .obj)");
  cmd->add_option("--preview", s->preview, "Write a shaded picture of the surface (.png)");
  cmd->add_flag("--pieces", s->pieces,
                "Under mpirun, each rank writes its own slab of the level set, with its weight grid, to -o's name "
                "with .<rank>-of-<ranks> before .vdb, and no rank holds the whole: the pieces' CSG union is the level "
                "set (no --mesh or --preview, which need it whole)");
}

/// The options of the method: its grids, its prior, its window and when it stops.
void addReconstructMethodOptions(CLI::App* cmd, const std::shared_ptr<ReconstructSettings>& s) {
  ReconstructionOptions& o = s->options;
  cmd->add_option_function<double>("--voxel-size", [s](double v) { s->options.voxelSize = v; },
                                   "Finest voxel size, world units (default: the scans' ray spacing)")
      ->check(numberIn(0.0, 1e6, true));
  cmd->add_option_function<int>("--levels", [s](int v) { s->options.levels = v; },
                                "Coarse-to-fine grids, each halving the voxel (default: coarsest ~64 across; 1 for scenes: depth frames, stations, LiDAR sweeps)")
      ->check(CLI::Range(1, 12));
  cmd->add_option_function<double>(
         "--beta", [s](double v) { s->options.beta = v; },
         "Surface-area prior, in finest voxels: larger is smoother, 0 off (default: max(0.5, sigma / voxel); 0 for scenes)")
      ->check(numberIn(0.0, 1e3));
  cmd->add_option_function<double>("--epsilon", [s](double v) { s->options.epsilon = v; },
                                   "Window width of a reading, world units (default: sigma; at least a voxel)")
      ->check(numberIn(0.0, 1e6, true));
  cmd->add_option_function<std::string>(
         "--window", [s](const std::string& w) { s->options.window = windowKindFromName(w); },
         "Window of a reading: gaussian (default) or binary")
      ->check(CLI::IsMember(windowKindNames()));
  cmd->add_option("--tolerance", o.tolerance, "A grid has converged below this rms speed (voxels per unit time)")
      ->check(numberIn(0.0, 1e3, true))
      ->capture_default_str();
  cmd->add_option("--max-iterations", o.maxIterations, "Iterations per grid at most (each grid runs min(4, this) at least)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--name", o.name, "Name of the output grid")->capture_default_str();
  cmd->add_flag("--linear", s->linear, "Only the linear solution (zero set of g, VRIP-style fusion), no evolution");
}

/// The options of reading the scans.
void addReconstructScanOptions(CLI::App* cmd, const std::shared_ptr<ReconstructSettings>& s) {
  cmd->add_option("--toward-scanner", s->towardScanner,
                  "Stanford scans: direction toward the scanner in the scan frame, x,y,z (default 0,0,1)")
      ->check(threeNumbers());
  cmd->add_option("--sigma", s->sigma, "Noise of a reading, world units (default: from the scans; PTX, point clouds: 0.002)")
      ->check(numberIn(0.0, 1e6, true));
  cmd->add_option("--depth-scale", s->depthScale,
                  "Depth frames: metres per 16-bit PNG unit (default: 0.001; TUM RGB-D folders 0.0002)")
      ->check(numberIn(0.0, 1.0, true));
  cmd->add_option("--max-depth", s->maxDepth, "Depth frames: drop readings deeper than this, metres (default: none)")
      ->check(numberIn(0.0, 1e6, true));
  cmd->add_option("--frame-stride", s->frameStride, "Depth frames: use every n-th frame")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
}

/// The options of the preview, the mesh and the run: threads, memory and what is printed.
void addReconstructRunOptions(CLI::App* cmd, const std::shared_ptr<ReconstructSettings>& s) {
  cmd->add_option("--view", s->view,
                  "Preview: direction from the surface toward the camera, x,y,z (default: for scenes, the "
                  "first frame's camera, inside the scene)")
      ->check(threeNumbers());
  cmd->add_option("--up", s->up, "Preview: the world direction that is up in the picture, x,y,z (default 0,1,0)")
      ->check(threeNumbers());
  addTrimUnseenOptions(cmd, s->trimUnseen, "Mesh and preview",
                       "Default: on for scenes (depth frames, stations, LiDAR sweeps), off for objects (Stanford scans, parallel rays).");
  cmd->add_option("--threads", s->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->add_option("--max-memory", s->maxMemoryGiB,
                  "Memory to use at most, GiB (default: the machine's); a run that would need more stops at once "
                  "and says which voxel size fits")
      ->check(numberIn(0.0, 1e6, true));
  cmd->add_flag("--json", s->json, "Print the summary as JSON (no progress line)");
  cmd->add_flag("-q,--quiet", s->quiet, "Print nothing but errors (and skip measuring the fit to the scans, which only the summary shows)");
}

}  // namespace

Command addReconstructCommand(CLI::App& app) {
  auto s = std::make_shared<ReconstructSettings>();
  CLI::App* cmd = app.add_subcommand(
      "reconstruct", "Reconstruct a surface from registered range scans (the MAP level-set method of Whitaker 1998)");
  addReconstructInputsAndOutputs(cmd, s);
  addReconstructMethodOptions(cmd, s);
  addReconstructScanOptions(cmd, s);
  addReconstructRunOptions(cmd, s);
  cmd->footer(
      "Examples:\n"
      "  levelfuse reconstruct bunny/bun.conf -o bunny.vdb --mesh bunny.ply --preview bunny.png\n"
      "  levelfuse reconstruct bunny/bun.conf --voxel-size 0.00025 --beta 1 -o fine.vdb\n"
      "  levelfuse reconstruct dragon/dragonStandRight.conf --toward-scanner 0.46,0.04,0.89 -o dragon.vdb\n"
      "  levelfuse synth --shape torus --noise 0.2 -o torus-scans && \\\n"
      "    levelfuse reconstruct torus-scans/scans.json --preview torus.png --json\n"
      "  levelfuse reconstruct 7scenes/ --frame-stride 2 --voxel-size 0.01 -o room.vdb\n"
      "  levelfuse reconstruct rgbd_dataset_freiburg1_xyz/ --max-depth 3 --voxel-size 0.01 --mesh desk.ply\n"
      "Outputs are written together, whole, or not at all; Ctrl-C stops any phase and writes nothing.");
  return {cmd, [s] { return runReconstruct(*s); }};
}

}  // namespace levelfuse::cli

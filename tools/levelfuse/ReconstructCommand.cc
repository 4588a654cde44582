// levelfuse reconstruct: range scans in, a level set, a mesh and a picture out.

#include "Cancellation.h"
#include "Commands.h"
#include "Job.h"
#include "ProgressBar.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/outputs/MeshFile.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/RunSummary.h>
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
  if (s.maxMemoryGiB > 0.0)
    s.options.memoryBudget = MemoryBudget(static_cast<std::uint64_t>(s.maxMemoryGiB * 1073741824.0));
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
struct Inputs : NumberedScans {
  std::optional<shapes::AnalyticShape> truth;
  /// Resolved from every rank's scans where the ranks read them in parts
  /// (loadTeamInputs); else from these scans once they are read (prepare).
  std::optional<ReconstructionSettings> settings;
};

/// Reads the scans of the inputs that `wanted` picks by their number among
/// all the inputs' scans (from 0, in order), every scan if it is not given.
Inputs loadInputs(const ReconstructSettings& s, ProgressBar& bar, const std::function<bool(std::size_t)>& wanted = {}) {
  enterPhase("loading");
  io::ScanLoadOptions load;
  load.memoryBudget = s.options.memoryBudget;
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

/// The scans of the inputs this rank of an MPI `team` needs (readTeamScans),
/// and the settings resolved from all of them: every scan at the rank that
/// measures and writes the whole surface (the fit and the colour read them
/// all). `cut` is set to this rank's slab of the data where the ranks share it.
Inputs loadTeamInputs(const ReconstructSettings& s, ProgressBar& bar, const SlabTeam& team,
                      std::optional<SharedDataSlab>& cut) {
  std::optional<shapes::AnalyticShape> truth;
  const NumberedScanReader read = [&](const std::function<bool(std::size_t)>& wanted) {
    Inputs part = loadInputs(s, bar, wanted);
    if (!truth) truth = std::move(part.truth);
    return static_cast<NumberedScans>(std::move(part));
  };
  const bool measuresTheSurface = leadsTheJob() && !s.pieces;
  TeamShare share;
  try {
    share = readTeamScans(read, s.options, measuresTheSurface, team, cancellationInterrupter());
  } catch (const std::invalid_argument& e) {
    throw ofTheInputs(s, e);
  }
  Inputs in;
  static_cast<NumberedScans&>(in) = std::move(share.held);
  in.truth = std::move(truth);
  in.settings = share.settings;
  cut = share.slab;
  return in;
}

/// The settings of the run, resolved once: from every rank's scans where the
/// ranks read them in parts, else from the scans read.
ReconstructionSettings settingsOf(const Inputs& in, const ReconstructSettings& s) {
  if (in.settings) return *in.settings;
  try {
    return resolveReconstructionSettings(s.options, in.scans.summary);
  } catch (const std::invalid_argument& e) {
    throw ofTheInputs(s, e);
  }
}

ScansReconstruction prepare(Inputs& in, const ReconstructionSettings& settings, const ReconstructSettings& s,
                            ProgressBar& bar, const SharedDataSlab* cut) {
  try {
    if (settings.dataTerm == DataTermSource::kGrids) enterPhase("integrating");
    // Under mpirun the ranks share the evolution, and each may integrate its slab of the data alone.
    return prepareReconstruction(
        std::move(in.scans), settings, [&](std::size_t done, std::size_t total) { bar.integrating(done, total); },
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

/// What the run did (recon/RunSummary.h): the scans, the settings, the
/// grids, the time and the fit; the caller adds the outputs and the ranks.
RunSummary runSummary(const ReconstructSettings& s, const Reconstructor& reconstructor,
                      const ReconstructionResult& result, const Measures& m, double seconds) {
  RunSummary summary;
  summary.inputs = s.inputs;
  summary.scans = reconstructor.summary().scans();
  summary.points = m.points;
  summary.readings = m.readings;
  summary.linear = s.linear;
  summary.scene = reconstructor.summary().aScene();
  summary.settings = reconstructor.settings();
  summary.levels = result.levels;
  summary.peakEngineBytes = result.peakEngineBytes;
  summary.fit = m.fit;
  summary.fitStride = m.fitSample;
  summary.phases = runPhases(result);
  summary.seconds = seconds;
  return summary;
}

/// The summary's line of the fit to the points.
void printFit(const RunSummary& r) {
  if (!r.fit) {
    std::cout << "  fit to the points: not measured, the surface is in pieces (--pieces)\n";
    return;
  }
  const DataFit& fit = *r.fit;
  std::cout << "  fit to the points"
            << (r.fitStride > 1 ? " (a sample of " + withCommas(fit.readings) + ": one reading in " +
                                      std::to_string(r.fitStride) + " along each row and column of each scan)"
                                : std::string())
            << ": mean " << length(fit.mean) << ", median " << length(fit.median) << ", 90% " << length(fit.p90)
            << "; " << fixed(100.0 * fit.withinVoxel, 4) << "% within a voxel, " << fixed(100.0 * fit.beyondBand, 3)
            << "% beyond the band\n";
}

/// The summary's line of the time taken: in all, of CPU, and per phase (those
/// of at least a hundredth of a second).
void printTimes(const RunSummary& r) {
  std::cout << "  " << duration(r.seconds) << " (CPU " << duration(r.cpuSeconds) << ")";
  const char* separator = ": ";
  for (const PhaseTime& phase : r.phases) {
    if (phase.seconds < 0.005) continue;
    std::cout << separator << phase.name << " " << duration(phase.seconds);
    separator = ", ";
  }
  std::cout << "\n";
}

/// The summary's lines of the files written.
void printWritten(const RunSummary& r) {
  for (const std::string& piece : r.levelSetPieces)
    std::cout << "  wrote " << piece << " (a piece of the closed level set, " << r.levelSetPieces.size()
              << " in all, and its weight grid)\n";
  if (!r.levelSetFile.empty())
    std::cout << "  wrote " << r.levelSetFile << " (the closed level set and its weight grid)\n";
  if (!r.meshFile.empty())
    std::cout << "  wrote " << r.meshFile << " (" << withCommas(r.triangles) << " triangles"
              << (r.trimmedUnseen ? ", unseen parts left out" : "") << ")\n";
  if (!r.previewFile.empty()) std::cout << "  wrote " << r.previewFile << "\n";
}

/// The summary's lines of an MPI job's ranks, one each.
void printRanks(const RunSummary& r) {
  std::uint64_t iterations = 0;
  for (const LevelReport& l : r.levels) iterations += static_cast<std::uint64_t>(l.iterations);
  iterations = std::max<std::uint64_t>(iterations, 1);
  std::cout << "  " << r.processes.size() << " MPI ranks, one slab of every grid each:\n";
  for (std::size_t k = 0; k < r.processes.size(); ++k) {
    const ProcessFacts& rank = r.processes[k];
    std::cout << "    rank " << k << ": " << withCommas(rank.leafNodes) << " leaf nodes of the finest grid, engine "
              << mebibytes(rank.engineBytes)
              << (rank.dataTermBytes > 0 ? ", data term " + mebibytes(rank.dataTermBytes) : std::string()) << ", "
              << withCommas(rank.scansHeld) << (rank.scansHeld == 1 ? " scan" : " scans") << ", process peak "
              << mebibytes(rank.peakBytes) << ", " << fixed(rank.seconds, 3) << " s to the end of the evolution, "
              << mebibytes(rank.ghostBytes) << " of ghosts sent (" << mebibytes(rank.ghostBytes / iterations)
              << " an iteration)\n";
  }
}

void printText(const RunSummary& r) {
  const ReconstructionSettings& o = r.settings;
  std::cout << "levelfuse reconstruct: " << r.scans << " scans, " << withCommas(r.points) << " points"
            << (r.points != r.readings ? " (" + withCommas(r.readings) + " readings of their range maps)"
                                       : std::string())
            << " (" << joined(r.inputs) << ")\n"
            << "  voxel " << length(o.voxelSize) << ", " << o.levels << (o.levels == 1 ? " grid" : " grids")
            << ", beta " << fixed(o.beta) << " voxels, window " << length(o.epsilon) << "\n";
  if (r.linear) std::cout << "  the linear solution (zero set of g), no evolution\n";
  for (const LevelReport& l : r.levels)
    std::cout << "  grid " << length(l.voxelSize) << ": " << l.iterations << " iterations ("
              << (l.converged ? "converged" : l.settled ? "settled" : "iteration limit") << "), "
              << withCommas(l.activeSetVoxels) << " voxels in the active set, " << fixed(l.seconds, 3) << " s\n";
  std::cout << "  surface: " << withCommas(r.narrowBandVoxels) << " narrow-band voxels; memory: engine "
            << mebibytes(r.peakEngineBytes)
            << (r.dataTermBytes > 0 ? ", data term " + mebibytes(r.dataTermBytes) : std::string()) << ", process peak "
            << mebibytes(r.peakMemoryBytes) << (r.processes.size() > 1 ? " (rank 0)" : "") << "\n";
  if (r.processes.size() > 1) printRanks(r);
  printFit(r);
  if (r.truth)
    std::cout << "  error against the true " << r.truth->shape << (r.truth->whereSeen ? " where seen" : "")
              << ": rms " << length(r.truth->rms) << " (" << fixed(r.truth->rms / o.voxelSize, 3) << " voxel)\n";
  printTimes(r);
  printWritten(r);
}

/// The summary, as JSON (--json) or as text (not with --quiet), with the
/// process's peak memory and CPU time as it is printed.
void printSummary(RunSummary summary, const ReconstructSettings& s) {
  recordProcessUsage(summary);
  if (s.json) std::cout << runSummaryJson(summary) << "\n";
  else if (!s.quiet) printText(summary);
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
                   const std::vector<ProcessFacts>& ranks, double seconds) {
  const std::uint64_t bandVoxels = totalOverJob(result.levelSet->activeVoxelCount());
  writePieceWithTheOthers(result, s);
  if (!leadsTheJob()) return kExitSuccess;
  RunSummary summary = runSummary(s, *made.reconstructor, result, countsOf(made), seconds);
  summary.narrowBandVoxels = bandVoxels;
  summary.dataTermBytes = dataTermBytesOf(made, result);
  summary.processes = ranks;
  summary.levelSetPieces = pieceFiles(s);
  printSummary(std::move(summary), s);
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
  ScansReconstruction made = prepare(inputs, settingsOf(inputs, s), s, bar, cut ? &*cut : nullptr);
  const Reconstructor& reconstructor = *made.reconstructor;
  const Presentation shown = presentationOf(reconstructor, s);
  if (s.linear && !leadsTheJob()) return kExitSuccess;  // the linear solution is not shared
  ReconstructionResult result = reconstructSurface(reconstructor, s, shown, bar);
  const std::uint64_t dataTermBytes = dataTermBytesOf(made, result);
  std::vector<ProcessFacts> ranks;
  if (!s.linear)
    ranks = gatherRankFacts(ProcessFacts{std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                                      peakResidentBytes(), result.peakEngineBytes,
                                      result.levels.empty() ? 0 : result.levels.back().ownLeafNodes,
                                      ghostBytesSent(), dataTermBytes, scansHeld});
  const auto secondsSoFar = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(); };
  if (s.pieces) return finishInPieces(s, made, result, ranks, secondsSoFar());
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
  RunSummary summary = runSummary(s, reconstructor, result, measures, secondsSoFar());
  summary.narrowBandVoxels = result.levelSet->activeVoxelCount();
  summary.dataTermBytes = dataTermBytes;
  summary.processes = ranks;
  summary.levelSetFile = s.output;
  summary.meshFile = s.mesh;
  summary.previewFile = s.preview;
  summary.triangles = triangles;
  summary.trimmedUnseen = shown.trim;
  if (inputs.truth && measures.truthRms >= 0.0)
    summary.truth = TruthError{inputs.truth->name(), measures.truthRms, shown.trim};
  if (summaryShown) printSummary(std::move(summary), s);
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

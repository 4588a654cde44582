// levelfuse: what a run did, said once: the scans, the settings, every grid,
// the memory, the time, the fit and the outputs. The converter prints it (and
// writes it as JSON with --json); the Python module's Result.summary is the
// same JSON as a dict.
#pragma once

#include <levelfuse/core/PhaseClock.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/recon/Reconstructor.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse {

/// What one process of a team did (an MPI job's rank).
struct ProcessFacts {
  double seconds = 0.0;             ///< from its start to the end of the evolution
  std::uint64_t peakBytes = 0;      ///< its peak resident memory
  std::uint64_t engineBytes = 0;    ///< its sparse field's, at the largest
  std::uint64_t leafNodes = 0;      ///< its own leaf nodes of the finest grid
  std::uint64_t ghostBytes = 0;     ///< the ghosts it sent its neighbours, every grid and iteration
  std::uint64_t dataTermBytes = 0;  ///< its grids of the data term (0 with the data term from the maps)
  std::uint64_t scansHeld = 0;      ///< the scans it held (those its slab needs, where the team shares the data)
};

/// The error of a surface against the shape a synthetic scan set was made of.
struct TruthError {
  std::string shape;      ///< the shape's name
  double rms = 0.0;       ///< world units
  bool whereSeen = false; ///< measured on the surface seen (the unseen left out), else on the whole
};

struct RunSummary {
  std::vector<std::string> inputs;  ///< the run's inputs, as given
  std::size_t scans = 0;
  std::size_t points = 0;    ///< what the scanners measured
  std::size_t readings = 0;  ///< of the range maps made of them
  bool linear = false;       ///< the linear solution alone, no evolution
  bool scene = false;        ///< scans of a scene (ScanSummary::aScene)
  ReconstructionSettings settings;
  std::vector<LevelReport> levels;
  std::size_t narrowBandVoxels = 0;
  std::size_t peakEngineBytes = 0;
  std::uint64_t dataTermBytes = 0;    ///< the grids of the data term at their largest
  std::uint64_t peakMemoryBytes = 0;  ///< the process's peak resident memory
  std::optional<DataFit> fit;         ///< not measured: absent
  int fitStride = 1;                  ///< every stride-th reading along each row and column measured
  double seconds = 0.0;
  double cpuSeconds = 0.0;
  std::vector<PhaseTime> phases;
  std::string levelSetFile;                  ///< the .vdb written; empty: none
  std::vector<std::string> levelSetPieces;   ///< or a piece of it per process
  std::string meshFile;                    ///< empty: none written
  std::string previewFile;                 ///< empty: none written
  std::size_t triangles = 0;               ///< of the mesh written
  bool trimmedUnseen = false;              ///< the mesh and preview leave out what no scan saw
  std::vector<ProcessFacts> processes;     ///< every process's, on a team of more than one
  std::optional<TruthError> truth;
};

/// The process's peak memory and CPU time so far, into `summary`: as it is told.
void recordProcessUsage(RunSummary& summary);

/// The summary as JSON (two-space indents): the converter's --json output.
std::string runSummaryJson(const RunSummary& summary);

}  // namespace levelfuse

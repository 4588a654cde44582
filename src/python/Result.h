// levelfuse Python module: what a reconstruction hands to Python.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>
#include <vector>

namespace levelfuse::python {

namespace py = pybind11;

/// What a run made, before Python sees it (built without the GIL).
struct Outcome {
  ReconstructionResult result;
  ReconstructionSettings settings;
  bool linear = false;
  std::vector<std::string> inputs;
  std::size_t scans = 0, readings = 0, points = 0;
  std::optional<DataFit> fit;  ///< if measured
  int fitStride = 1;
  bool scene = false;  ///< the scans are a scene's (depth frames)
  std::optional<RangeMap> firstScan;  ///< a scene's preview looks from its camera
  double seconds = 0.0;
};

/// How a run is made: its method, what the summary measures, what it is of.
struct RunSettings {
  bool linear = false;  ///< the linear solution only (VRIP-style), no evolution
  bool fit = true;      ///< measure the fit to the scans for the summary
  std::vector<std::string> inputs;  ///< in the level set's levelfuse_inputs metadata
};

/// Runs `reconstructor` (the evolution, or the linear solution) and measures
/// what the summary says; `progress` and `interrupter` as Reconstructor::run's.
/// The caller's fusion, if the reconstructor is on one, may let its grids go
/// (`beforeFit`) before the fit is measured on `scans`.
Outcome runReconstruction(const Reconstructor& reconstructor, const RangeMapSequence& scans,
                          const RunSettings& settings, const ProgressCallback& progress,
                          const Interrupter& interrupter, const std::function<RangeMapSequence()>& beforeFit = {});

/// levelfuse.Result of an outcome (GIL held).
py::object resultOf(Outcome outcome);

}  // namespace levelfuse::python

// levelfuse Python module: levelfuse.reconstruct, the converter's
// reconstruction of scan files or of range maps from numpy.

#include "Arrays.h"
#include "Bindings.h"
#include "Cancellation.h"
#include "Options.h"
#include "Result.h"

#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/scan/PackedRangeMap.h>

#include <pybind11/stl.h>

#include <limits>

namespace levelfuse::python {
namespace {

/// The scans a reconstruction is of, read and held packed.
struct Inputs {
  PackedScans scans;
  std::optional<RangeMap> firstScan;  ///< a scene's preview looks from its camera
  std::vector<std::string> names;     ///< the files, for the metadata
};

bool isPath(const py::handle& value) {
  return py::isinstance<py::str>(value) || py::isinstance(value, py::module_::import("os").attr("PathLike"));
}

/// The scans `scans` names: paths read as the converter reads them, or range maps (copied).
Inputs inputsFrom(const py::handle& scans, io::ScanLoadOptions load, ProgressRelay& relay,
                  Cancellation& cancellation) {
  std::vector<py::handle> items;
  if (isPath(scans) || py::isinstance<RangeMap>(scans)) items.push_back(scans);
  else if (py::isinstance<py::list>(scans) || py::isinstance<py::tuple>(scans))
    for (const py::handle item : scans) items.push_back(item);
  else
    throw py::type_error("scans must be a path, a levelfuse.RangeMap, or a list of either");
  if (items.empty()) throw py::value_error("scans: no scans given");
  Inputs in;
  std::vector<const RangeMap*> maps;
  for (const py::handle item : items) {
    if (isPath(item)) in.names.push_back(py::str(py::module_::import("os").attr("fspath")(item)).cast<std::string>());
    else if (py::isinstance<RangeMap>(item)) maps.push_back(&item.cast<const RangeMap&>());
    else throw py::type_error("scans must be paths or levelfuse.RangeMap objects, not a mix or other things");
  }
  if (!in.names.empty() && !maps.empty()) throw py::type_error("scans: give paths or range maps, not both");
  load.interrupter = cancellation.interrupter();
  load.progress = [&](std::size_t read, std::size_t total) { relay.count("loading", read, total); };
  load.take = [&](RangeMap&& map) {
    if (!in.firstScan) in.firstScan = map;
    in.scans.add(std::move(map));
  };
  runReleased(cancellation, &relay, [&] {
    for (const std::string& path : in.names) io::loadScans(path, load);
    for (const RangeMap* map : maps) load.take(RangeMap(*map));
    return 0;
  });
  if (!maps.empty()) in.names = {std::to_string(maps.size()) + " range maps from Python"};
  return in;
}

py::object reconstruct(const py::handle& scans, const py::object& progress, py::kwargs kw) {
  py::dict kwargs(kw);
  io::ScanLoadOptions load = takeLoadOptions(kwargs);
  ReconstructionOptions options = takeReconstructionOptions(kwargs);
  options.memoryBudget = load.memoryBudget;  // one keyword for the readers and the reconstruction
  RunSettings settings = takeRunSettings(kwargs, {});
  refuseUnknownKeywords(kwargs, "reconstruct");
  Cancellation cancellation;
  ProgressRelay relay(progress, cancellation);
  Inputs in = inputsFrom(scans, load, relay, cancellation);
  if (settings.inputs.empty()) settings.inputs = in.names;
  Outcome outcome = runReleased(cancellation, &relay, [&] {
    const ReconstructionSettings resolved = resolveReconstructionSettings(options, in.scans.summary);
    ScansReconstruction r = prepareReconstruction(
        std::move(in.scans), resolved,
        [&](std::size_t done, std::size_t total) { relay.count("integrating", done, total); },
        cancellation.interrupter());
    return runReconstruction(
        *r.reconstructor, r.scans, settings, [&](const ReconstructionProgress& p) { return relay.report(p); },
        cancellation.interrupter(), [&] {
          r.letTheGridsGo();
          return r.scans;
        });
  });
  outcome.firstScan = std::move(in.firstScan);
  return resultOf(std::move(outcome));
}

}  // namespace

void bindReconstruction(py::module_& m) {
  m.def("reconstruct", &reconstruct, py::arg("scans"), py::kw_only(), py::arg("progress") = py::none(),
        R"doc(Reconstructs a surface from scans, as `levelfuse reconstruct` does; returns a levelfuse.Result.

scans: a path (Stanford .conf, JSON manifest, folder of depth frames), a list of paths, or levelfuse.RangeMap
objects. Keywords (None or left out: derived from the data, as the converter derives them):
  voxel_size, levels, beta, epsilon, window='gaussian'|'binary', data_term='auto'|'per_map'|'grids',
  tolerance=0.05, patience=8, drift=0.025, min_iterations=4, max_iterations=300, name='surface',
  layers=2, max_step_change=0.45, curvature_step_limit=0.25, stiffness_step_limit=0.5, grain_size=4
  linear=False (the linear solution only), fit=True (measure the fit to the scans for the summary),
  inputs (names for the metadata), memory_budget (bytes the readers and the reconstruction may use;
  the machine's memory by default: what would need more raises levelfuse.InsufficientMemory or InputError)
  and for paths: depth_scale, sigma, toward_scanner, max_depth, frame_stride, pose_time_tolerance.
progress(dict) is called with the GIL held at each new stage and at most five times a second within one;
returning False (or raising) stops the work: levelfuse.Cancelled (or the callback's exception) is raised.
Ctrl-C raises KeyboardInterrupt.)doc");
}

}  // namespace levelfuse::python

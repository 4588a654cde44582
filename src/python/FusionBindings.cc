// levelfuse Python module: levelfuse.Fusion, range maps fused one at a time
// as depth video arrives, reconstructed when asked (recon/Fusion.h).

#include "Arrays.h"
#include "Bindings.h"
#include "Cancellation.h"
#include "Options.h"
#include "Result.h"
#include "Scans.h"

#include <levelfuse/recon/Fusion.h>

#include <pybind11/stl.h>

#include <memory>

namespace levelfuse::python {
namespace {

/// A fusion and the first map it took (a scene's preview looks from its camera).
struct PyFusion {
  std::unique_ptr<Fusion> fusion;
  std::optional<RangeMap> firstScan;

  void integrate(const RangeMap& map) {
    if (!firstScan) firstScan = map;
    py::gil_scoped_release released;
    fusion->integrate(map);
  }
};

std::unique_ptr<PyFusion> makeFusion(double voxelSize, int levels, const py::handle& epsilon,
                                     const std::string& window, std::size_t grainSize) {
  FusionSettings s;
  s.voxelSize = numberFrom(py::float_(voxelSize), "voxel_size", true);
  s.levels = levels;
  s.epsilon = epsilon.is_none() ? s.voxelSize : numberFrom(epsilon, "epsilon", true);
  s.window = windowKindFromName(window);
  s.grainSize = grainSize;
  return std::make_unique<PyFusion>(PyFusion{std::make_unique<Fusion>(s), std::nullopt});
}

/// The fusion's reconstruction (or linear solution) from the maps so far.
py::object reconstructFusion(const PyFusion& f, bool linear, const py::object& progress, py::dict kwargs) {
  const ReconstructionOptions options = takeReconstructionOptions(kwargs);
  RunSettings settings =
      takeRunSettings(kwargs, {std::to_string(f.fusion->scanCount()) + " range maps fused one at a time"});
  if (linear) settings.linear = true;
  refuseUnknownKeywords(kwargs, linear ? "linear_solution" : "reconstruct");
  Cancellation cancellation;
  ProgressRelay relay(progress, cancellation);
  Outcome outcome = runReleased(cancellation, &relay, [&] {
    const Reconstructor reconstructor(*f.fusion, options);
    return runReconstruction(
        reconstructor, f.fusion->scans(), settings, [&](const ReconstructionProgress& p) { return relay.report(p); },
        cancellation.interrupter());
  });
  outcome.firstScan = f.firstScan;
  return resultOf(std::move(outcome));
}

void integrateDepthFrame(PyFusion& f, const py::handle& depth, const py::handle& K, const py::handle& pose,
                         double depthScale, const py::handle& sigma, const py::handle& maxDepth,
                         const std::string& name) {
  f.integrate(depthFrameFrom(depth, K, pose, depthScale, sigma, maxDepth, name));
}

py::object reconstructFused(const PyFusion& f, const py::object& progress, py::kwargs kw) {
  return reconstructFusion(f, false, progress, py::dict(kw));
}

py::object linearSolutionFused(const PyFusion& f, const py::object& progress, py::kwargs kw) {
  return reconstructFusion(f, true, progress, py::dict(kw));
}

}  // namespace

void bindFusion(py::module_& m) {
  py::class_<PyFusion>(m, "Fusion", R"doc(Range maps fused one at a time, as depth video arrives: each map's data
term goes into sparse grids at once and the map is kept packed (about 120 KB a depth frame) for space carving.
reconstruct() and linear_solution() may be asked for at any time, as often as wanted, while more maps come.

  fusion = levelfuse.Fusion(voxel_size=0.01)
  for depth, pose in frames: fusion.integrate(depth, K, pose)
  result = fusion.reconstruct())doc")
      .def(py::init(&makeFusion), py::arg("voxel_size"), py::kw_only(), py::arg("levels") = 1,
           py::arg("epsilon") = py::none(), py::arg("window") = "gaussian", py::arg("grain_size") = 1,
           "voxel_size: the finest grid's (world units); levels: grids, each halving the voxel; epsilon: the "
           "window's width (world units; default the voxel size, the narrowest a window gets).")
      .def(
          "integrate", [](PyFusion& f, const RangeMap& map) { f.integrate(map); }, py::arg("map"),
          "Adds a levelfuse.RangeMap's data term.")
      .def("integrate", &integrateDepthFrame, py::arg("depth"), py::arg("K"), py::arg("pose"), py::kw_only(),
           py::arg("depth_scale") = 0.001, py::arg("sigma") = py::none(), py::arg("max_depth") = py::none(),
           py::arg("name") = "",
           "Adds a depth frame (as levelfuse.RangeMap.pinhole takes it): depth (H, W) float32 metres or uint16, K "
           "3x3, pose 4x4 camera-to-world.")
      .def("reconstruct", &reconstructFused, py::kw_only(), py::arg("progress") = py::none(),
           "The MAP reconstruction from the maps so far (the keywords of levelfuse.reconstruct; voxel_size, "
           "levels, window and epsilon are the fusion's).")
      .def("linear_solution", &linearSolutionFused, py::kw_only(), py::arg("progress") = py::none(),
           "The linear solution on the finest grid from the maps so far: VRIP-style fusion, no evolution.")
      .def_property_readonly("scan_count", [](const PyFusion& f) { return f.fusion->scanCount(); })
      .def_property_readonly("voxel_size", [](const PyFusion& f) { return f.fusion->settings().voxelSize; })
      .def_property_readonly("levels", [](const PyFusion& f) { return f.fusion->levels(); })
      .def_property_readonly("epsilon", [](const PyFusion& f) { return f.fusion->settings().epsilon; })
      .def_property_readonly("memory_bytes", [](const PyFusion& f) { return f.fusion->memoryBytes(); },
                             "Memory held: the grids, the packed maps and space carving's votes kept between answers (bytes).")
      .def("__repr__", [](const PyFusion& f) {
        return "<levelfuse.Fusion: " + std::to_string(f.fusion->scanCount()) + " maps at " +
               std::to_string(f.fusion->settings().voxelSize) + ">";
      });
}

}  // namespace levelfuse::python

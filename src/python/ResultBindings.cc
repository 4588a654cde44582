// levelfuse Python module: levelfuse.Result (the surface, its weight grid and
// the summary) and levelfuse.Mesh.

#include "Arrays.h"
#include "Bindings.h"
#include "Grids.h"
#include "PyOpenVdb.h"
#include "Result.h"

#include <levelfuse/io/outputs/MeshFile.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/RunSummary.h>
#include <levelfuse/recon/ScansReconstruction.h>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>


namespace levelfuse::python {
namespace {

/// The result held for Python.
struct Result {
  Outcome outcome;
  py::dict summary;
};

/// The run's summary (recon/RunSummary.h), the converter's --json output, as a dict.
py::dict summaryOf(const Outcome& o) {
  RunSummary summary;
  summary.inputs = o.inputs;
  summary.scans = o.scans;
  summary.points = o.points;
  summary.readings = o.readings;
  summary.linear = o.linear;
  summary.scene = o.scene;
  summary.settings = o.settings;
  summary.levels = o.result.levels;
  summary.narrowBandVoxels = o.result.levelSet->activeVoxelCount();
  summary.peakEngineBytes = o.result.peakEngineBytes;
  summary.fit = o.fit;
  summary.fitStride = o.fitStride;
  summary.phases = o.result.phases;
  summary.seconds = o.seconds;
  recordProcessUsage(summary);
  return py::module_::import("json").attr("loads")(runSummaryJson(summary));
}

/// A mesh held for Python: numpy views of its vertices and triangles.
struct Mesh {
  TriangleMesh mesh;
};

py::array verticesOf(const py::object& self) {
  const TriangleMesh& m = self.cast<const Mesh&>().mesh;
  return py::array_t<float>({static_cast<py::ssize_t>(m.vertexCount()), py::ssize_t{3}}, m.xyz.data(), self);
}

py::array trianglesOf(const py::object& self) {
  const TriangleMesh& m = self.cast<const Mesh&>().mesh;
  return py::array_t<std::uint32_t>({static_cast<py::ssize_t>(m.triangleCount()), py::ssize_t{3}},
                                    m.triangles.data(), self);
}

py::object coloursOf(const py::object& self) {
  const TriangleMesh& m = self.cast<const Mesh&>().mesh;
  if (!m.hasColours()) return py::none();
  return py::array_t<std::uint8_t>({static_cast<py::ssize_t>(m.vertexCount()), py::ssize_t{3}}, m.rgb.data(), self);
}

/// The grids a result writes: the level set, its weight and its colour if it has one.
openvdb::GridCPtrVec gridsOf(const Result& r) {
  openvdb::GridCPtrVec grids{r.outcome.result.levelSet, r.outcome.result.weight};
  if (r.outcome.result.colour) grids.push_back(r.outcome.result.colour);
  return grids;
}

/// Whether the result's mesh or preview leaves out what no scan observed.
bool trims(const Result& r, const std::optional<bool>& asked) {
  const bool trim = trimsUnseen(r.outcome.scene, asked);
  if (trim && !r.outcome.result.weight)
    throw py::value_error("trim_unseen: this result has no weight grid to trim by");
  return trim;
}

Mesh meshOf(const Result& r, double adaptivity, const std::optional<bool>& trimUnseen) {
  const bool trim = trims(r, trimUnseen);
  py::gil_scoped_release released;
  return Mesh{meshShown(*r.outcome.result.levelSet, trim ? r.outcome.result.weight.get() : nullptr, adaptivity,
                        r.outcome.result.colour.get())};
}

io::PreviewOptions previewOptionsOf(const Result& r, int width, const std::optional<int>& height,
                                    const py::handle& view, const py::handle& up,
                                    const std::optional<bool>& trimUnseen) {
  io::PreviewOptions options;
  options.width = width;
  if (height) options.height = *height;
  else options.height = width * 3 / 4;
  if (!view.is_none()) options.toward = vec3From(view, "view");
  if (!up.is_none()) options.up = vec3From(up, "up");
  // A scene is seen from where its first frame's camera stood, unless a view is asked for.
  const bool fromItsCamera = r.outcome.scene && view.is_none() && r.outcome.firstScan;
  options = previewShown(options, fromItsCamera ? &*r.outcome.firstScan : nullptr,
                         trims(r, trimUnseen) ? r.outcome.result.weight : nullptr);
  if (fromItsCamera && height) options.height = *height;
  options.colour = r.outcome.result.colour;
  return options;
}

void writeMeshFile(const Mesh& held, const std::string& path) {
  io::requireMeshFileName(path);
  py::gil_scoped_release released;
  io::writeMesh(path, held.mesh);
}

std::string meshRepr(const Mesh& held) {
  return "<levelfuse.Mesh: " + std::to_string(held.mesh.vertexCount()) + " vertices, " +
         std::to_string(held.mesh.triangleCount()) + " triangles>";
}

void bindMesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", "A triangle mesh in world units, counter-clockwise seen from outside.")
      .def_property_readonly("vertices", &verticesOf, "(N, 3) float32, a view of the mesh's vertices.")
      .def_property_readonly("triangles", &trianglesOf, "(M, 3) uint32 vertex indices, a view.")
      .def_property_readonly("colours", &coloursOf,
                             "(N, 3) uint8 red, green, blue per vertex, a view; None if the scans had no colour.")
      .def_property_readonly("area", [](const Mesh& held) { return held.mesh.area(); })
      .def_property_readonly("volume", [](const Mesh& held) { return held.mesh.volume(); })
      .def("write", &writeMeshFile, py::arg("path"), "Writes the mesh as .ply (binary) or .obj, atomically.")
      .def("__repr__", &meshRepr);
}

Mesh resultMesh(const Result& r, double adaptivity, std::optional<bool> trim) { return meshOf(r, adaptivity, trim); }

void writeResultVdb(const Result& r, const std::string& path) {
  py::gil_scoped_release released;
  io::writeVdb(path, gridsOf(r));
}

void writeResultMesh(const Result& r, const std::string& path, double adaptivity, std::optional<bool> trim) {
  io::requireMeshFileName(path);
  const Mesh mesh = meshOf(r, adaptivity, trim);
  py::gil_scoped_release released;
  io::writeMesh(path, mesh.mesh);
}

py::array_t<std::uint8_t> previewOf(const Result& r, int width, std::optional<int> height, const py::handle& view,
                                    const py::handle& up, std::optional<bool> trim) {
  const io::PreviewOptions options = previewOptionsOf(r, width, height, view, up, trim);
  io::PreviewImage image;
  {
    py::gil_scoped_release released;
    image = io::renderPreview(*r.outcome.result.levelSet, options);
  }
  py::array_t<std::uint8_t> out(
      {static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), py::ssize_t{3}});
  std::copy(image.rgb.begin(), image.rgb.end(), out.mutable_data());
  return out;
}

void writeResultPreview(const Result& r, const std::string& path, int width, std::optional<int> height,
                        const py::handle& view, const py::handle& up, std::optional<bool> trim) {
  const io::PreviewOptions options = previewOptionsOf(r, width, height, view, up, trim);
  py::gil_scoped_release released;
  io::writePreviewPng(*r.outcome.result.levelSet, path, options);
}

std::string resultRepr(const Result& r) {
  return "<levelfuse.Result: " + std::string(r.outcome.linear ? "linear solution" : "MAP evolution") + ", " +
         std::to_string(r.outcome.result.levelSet->activeVoxelCount()) + " narrow-band voxels>";
}

/// Result's grids: the level set, its weight and colour, as pyopenvdb's and as levelfuse.Grid.
void defineResultGrids(py::class_<Result>& result) {
  result
      .def_property_readonly(
          "level_set", [](const Result& r) { return gridForPython(r.outcome.result.levelSet); },
          "The level set: a pyopenvdb.FloatGrid sharing it where pyopenvdb is installed, else a levelfuse.Grid.")
      .def_property_readonly(
          "weight", [](const Result& r) { return gridForPython(r.outcome.result.weight); },
          "The weight grid: a pyopenvdb.FloatGrid where pyopenvdb is installed, else a levelfuse.Grid.")
      .def_property_readonly(
          "colour", [](const Result& r) { return colourForPython(r.outcome.result.colour); },
          "The colour the scans saw on the surface, a pyopenvdb.Vec3SGrid named Cd (red, green, blue from 0 to "
          "1); None if no scan had colour.")
      .def_property_readonly(
          "grid", [](const Result& r) { return r.outcome.result.levelSet; }, "The level set as a levelfuse.Grid.")
      .def_property_readonly(
          "weight_grid", [](const Result& r) { return r.outcome.result.weight; },
          "The weight grid as a levelfuse.Grid.");
}

/// Result's outputs: its mesh, .vdb file and bytes, and its picture.
void defineResultOutputs(py::class_<Result>& result) {
  result
      .def("mesh", &resultMesh, py::kw_only(), py::arg("adaptivity") = 0.0, py::arg("trim_unseen") = py::none(),
           "The zero set as a levelfuse.Mesh. adaptivity in [0, 1]; trim_unseen leaves out what no scan "
           "observed (default: for scenes, i.e. depth frames).")
      .def("write_vdb", &writeResultVdb, py::arg("path"),
           "Writes the level set, its weight grid and its colour (if the scans had colour) to a .vdb file, as the "
           "converter's -o does.")
      .def(
          "vdb_bytes", [](const Result& r) { return vdbBytes(gridsOf(r)); }, "The bytes write_vdb writes.")
      .def("write_mesh", &writeResultMesh, py::arg("path"), py::kw_only(), py::arg("adaptivity") = 0.0,
           py::arg("trim_unseen") = py::none(), "Writes the mesh (.ply or .obj), as the converter's --mesh does.")
      .def("preview", &previewOf, py::kw_only(), py::arg("width") = 800, py::arg("height") = py::none(),
           py::arg("view") = py::none(), py::arg("up") = py::none(), py::arg("trim_unseen") = py::none(),
           "A shaded picture, (H, W, 3) uint8: objects seen from `view` (a direction toward the camera), scenes "
           "from their first frame's camera.")
      .def("write_preview", &writeResultPreview, py::arg("path"), py::kw_only(), py::arg("width") = 800,
           py::arg("height") = py::none(), py::arg("view") = py::none(), py::arg("up") = py::none(),
           py::arg("trim_unseen") = py::none(),
           "Writes the picture of preview() as a PNG, as the converter's --preview does.");
}

void bindResultClass(py::module_& m) {
  py::class_<Result> result(m, "Result",
                            "A reconstruction: the level set (negative inside, world units), its weight grid (the "
                            "readings that face the surface; 0 where no scan saw it) and the summary.");
  defineResultGrids(result);
  result.def_readonly("summary", &Result::summary,
                      "The run: scans, settings, per-grid reports, time, and the fit to the scans (metres or the "
                      "scans' units).");
  defineResultOutputs(result);
  result.def("__repr__", &resultRepr);
}

}  // namespace

py::object resultOf(Outcome outcome) {
  Result r{std::move(outcome), {}};
  r.summary = summaryOf(r.outcome);
  return py::cast(std::move(r));
}

void bindResult(py::module_& m) {
  bindMesh(m);
  bindResultClass(m);
}

}  // namespace levelfuse::python

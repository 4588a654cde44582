// levelfuse Python module: levelfuse.Grid, an OpenVDB float grid (a level set
// or a weight grid) as numpy, .vdb bytes and files, and pyopenvdb grids.

#include "Arrays.h"
#include "Bindings.h"
#include "Grids.h"
#include "PyOpenVdb.h"

#include <levelfuse/io/vdb/VdbFile.h>

#include <openvdb/tools/Interpolation.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace levelfuse::python {
namespace {

using openvdb::FloatGrid;

/// The grid's active voxels in the tree's order: index coordinates (N, 3)
/// int32 and values (N,) float32.
py::tuple activeVoxels(const FloatGrid& grid) {
  const auto count = static_cast<py::ssize_t>(grid.activeVoxelCount());
  py::array_t<std::int32_t> coords({count, py::ssize_t{3}});
  py::array_t<float> values(count);
  std::int32_t* c = coords.mutable_data();
  float* v = values.mutable_data();
  {
    py::gil_scoped_release released;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
      if (it.isTileValue()) {
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        for (auto ijk = box.begin(); ijk; ++ijk) {
          for (int a = 0; a < 3; ++a) *c++ = (*ijk)[a];
          *v++ = *it;
        }
      } else {
        const openvdb::Coord ijk = it.getCoord();
        for (int a = 0; a < 3; ++a) *c++ = ijk[a];
        *v++ = *it;
      }
    }
  }
  return py::make_tuple(coords, values);
}

/// Trilinear samples of the grid at world points (N, 3).
py::array_t<float> sampleAt(const FloatGrid& grid, const py::handle& points) {
  const std::vector<openvdb::Vec3d> xs = pointsFrom(points, "points");
  py::array_t<float> out(static_cast<py::ssize_t>(xs.size()));
  float* o = out.mutable_data();
  py::gil_scoped_release released;
  const openvdb::tools::GridSampler<FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(
      grid.getConstAccessor(), grid.transform());
  for (std::size_t i = 0; i < xs.size(); ++i) o[i] = sampler.wsSample(xs[i]);
  return out;
}

/// The grid's metadata as Python values (strings, numbers, booleans; others as text).
py::dict metadataOf(const FloatGrid& grid) {
  py::dict d;
  for (auto it = grid.beginMeta(); it != grid.endMeta(); ++it) {
    const openvdb::Metadata& meta = *it->second;
    const std::string type = meta.typeName();
    py::object value;
    if (type == "string") value = py::str(static_cast<const openvdb::StringMetadata&>(meta).value());
    else if (type == "bool") value = py::bool_(static_cast<const openvdb::BoolMetadata&>(meta).value());
    else if (type == "float") value = py::float_(static_cast<const openvdb::FloatMetadata&>(meta).value());
    else if (type == "double") value = py::float_(static_cast<const openvdb::DoubleMetadata&>(meta).value());
    else if (type == "int32") value = py::int_(static_cast<const openvdb::Int32Metadata&>(meta).value());
    else if (type == "int64") value = py::int_(static_cast<const openvdb::Int64Metadata&>(meta).value());
    else value = py::str(meta.str());
    d[py::str(it->first)] = value;
  }
  return d;
}

}  // namespace

py::bytes vdbBytes(const openvdb::GridCPtrVec& grids) {
  std::string bytes;
  {
    py::gil_scoped_release released;
    const std::filesystem::path temporary = std::filesystem::temp_directory_path() /
                                            ("levelfuse-" + std::to_string(::getpid()) + "-" +
                                             std::to_string(reinterpret_cast<std::uintptr_t>(&bytes)) + ".vdb");
    io::writeVdb(temporary.string(), grids);
    std::ifstream in(temporary, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    std::filesystem::remove(temporary);
  }
  return py::bytes(bytes);
}

namespace {

py::array_t<double> indexToWorld(const FloatGrid& g, const py::handle& coords) {
  std::vector<openvdb::Vec3d> xs = pointsFrom(coords, "coords");
  for (openvdb::Vec3d& x : xs) x = g.indexToWorld(x);
  return numpyPoints(xs);
}

void writeGrid(FloatGrid::Ptr g, const std::string& path) {
  py::gil_scoped_release released;
  io::writeVdb(path, {g});
}

std::string gridRepr(const FloatGrid& g) {
  return "<levelfuse.Grid '" + g.getName() + "': " + FloatGrid::gridClassToString(g.getGridClass()) + ", " +
         std::to_string(g.activeVoxelCount()) + " active voxels of " + std::to_string(g.voxelSize()[0]) + ">";
}

void bindGrid(py::module_& m) {
  py::class_<FloatGrid, FloatGrid::Ptr>(m, "Grid",
                                        "An OpenVDB float grid: a level set (negative inside, world units) or a "
                                        "weight grid. to_pyopenvdb() shares it with pyopenvdb without a copy.")
      .def_property_readonly("name", &FloatGrid::getName)
      .def_property_readonly("voxel_size", [](const FloatGrid& g) { return g.voxelSize()[0]; },
                             "Edge of a voxel, world units.")
      .def_property_readonly("grid_class",
                             [](const FloatGrid& g) { return FloatGrid::gridClassToString(g.getGridClass()); })
      .def_property_readonly("background", [](const FloatGrid& g) { return g.background(); })
      .def_property_readonly("active_voxel_count", [](const FloatGrid& g) { return g.activeVoxelCount(); })
      .def_property_readonly("metadata", &metadataOf, "The grid's metadata (levelfuse_* for a reconstruction).")
      .def("active_voxels", &activeVoxels,
           "(coords, values): the active voxels' index coordinates, (N, 3) int32, and values, (N,) float32; "
           "world position = coords * voxel_size (index_to_world for the grid's full transform).")
      .def("index_to_world", &indexToWorld, py::arg("coords"),
           "World positions, (N, 3) float64, of index coordinates (N, 3).")
      .def("sample", &sampleAt, py::arg("points"),
           "Trilinear samples, (N,) float32, of the grid at world points (N, 3).")
      .def(
          "vdb_bytes", [](FloatGrid::Ptr g) { return vdbBytes({g}); },
          "The grid as the bytes of a .vdb file (the same grids give the same bytes).")
      .def("write", &writeGrid, py::arg("path"), "Writes the grid to a .vdb file, atomically.")
      .def("to_pyopenvdb", &toPyOpenVdb, "The grid as a pyopenvdb.FloatGrid sharing it (no copy).")
      .def_static(
          "from_pyopenvdb", [](const py::handle& g) { return gridFrom(g, "grid"); }, py::arg("grid"),
          "A pyopenvdb.FloatGrid as a levelfuse.Grid sharing it (no copy).")
      .def("__repr__", &gridRepr);
}

py::list readVdbGrids(const std::string& path) {
  openvdb::GridPtrVecPtr grids;
  {
    py::gil_scoped_release released;
    grids = io::readVdb(path);
  }
  py::list out;
  for (const openvdb::GridBase::Ptr& g : *grids)
    if (FloatGrid::Ptr f = openvdb::gridPtrCast<FloatGrid>(g)) out.append(py::cast(f));
  return out;
}

void writeVdbGrids(const std::string& path, const py::iterable& grids) {
  openvdb::GridCPtrVec all;
  for (const py::handle g : grids) all.push_back(gridFrom(g, "grids"));
  py::gil_scoped_release released;
  io::writeVdb(path, all);
}

/// read_vdb and write_vdb.
void bindVdbFiles(py::module_& m) {
  m.def("read_vdb", &readVdbGrids, py::arg("path"),
        "The float grids of a .vdb file, as levelfuse.Grid; InputError names a bad file.");
  m.def("write_vdb", &writeVdbGrids, py::arg("path"), py::arg("grids"),
        "Writes levelfuse.Grid or pyopenvdb.FloatGrid grids to a .vdb file, atomically, with the bytes levelfuse "
        "writes (the same grids give the same bytes).");
}

}  // namespace

void bindGrids(py::module_& m) {
  bindGrid(m);
  bindVdbFiles(m);
}

}  // namespace levelfuse::python

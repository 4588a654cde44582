// levelfuse Python module: grids shared with pyopenvdb.

#include "PyOpenVdb.h"

#include <boost/python.hpp>

namespace levelfuse::python {
namespace {

/// Imports pyopenvdb, whose import registers its grid types with Boost.Python.
bool importPyOpenVdb() {
  try {
    py::module_::import("pyopenvdb");
    return true;
  } catch (const py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) throw;
    return false;
  }
}

/// The grid as pyopenvdb's object sharing it; ImportError saying `elsewhere`
/// (where else the grid is at hand) if pyopenvdb cannot be imported.
template <typename GridPtr>
py::object sharedWithPyOpenVdb(GridPtr grid, const char* elsewhere) {
  if (!importPyOpenVdb())
    throw py::import_error(std::string("pyopenvdb is not installed (Debian: apt-get install python3-openvdb); ") +
                           elsewhere);
  boost::python::object shared(grid);
  return py::reinterpret_borrow<py::object>(shared.ptr());
}

}  // namespace

py::object toPyOpenVdb(openvdb::FloatGrid::Ptr grid) {
  return sharedWithPyOpenVdb(std::move(grid), "the grid is at hand as a levelfuse.Grid, as .vdb bytes (vdb_bytes) "
                                              "and as numpy (active_voxels)");
}

py::object colourForPython(openvdb::Vec3fGrid::Ptr grid) {
  if (!grid) return py::none();
  return sharedWithPyOpenVdb(std::move(grid), "the colour is at hand in the .vdb (write_vdb, vdb_bytes) and on "
                                              "the mesh (Mesh.colours)");
}

openvdb::FloatGrid::Ptr fromPyOpenVdb(const py::handle& value) {
  const py::handle type = py::type::handle_of(value);
  if (py::str(type.attr("__module__")).cast<std::string>() != "pyopenvdb") return nullptr;
  const boost::python::object held{boost::python::handle<>(boost::python::borrowed(value.ptr()))};
  boost::python::extract<openvdb::FloatGrid::Ptr> grid(held);
  return grid.check() ? grid() : nullptr;
}

py::object gridForPython(openvdb::FloatGrid::Ptr grid) {
  if (!grid) return py::none();
  if (importPyOpenVdb()) return toPyOpenVdb(std::move(grid));
  return py::cast(std::move(grid));
}

openvdb::FloatGrid::Ptr gridFrom(const py::handle& value, const std::string& name) {
  if (py::isinstance<openvdb::FloatGrid>(value)) return value.cast<openvdb::FloatGrid::Ptr>();
  if (openvdb::FloatGrid::Ptr grid = fromPyOpenVdb(value)) return grid;
  throw py::type_error(name + " must be a levelfuse.Grid or a pyopenvdb.FloatGrid, not " +
                       py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>());
}

}  // namespace levelfuse::python

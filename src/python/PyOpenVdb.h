// levelfuse Python module: grids crossing to and from pyopenvdb, OpenVDB's
// own Python binding (Debian's python3-openvdb), without a copy. pyopenvdb
// is built with Boost.Python and registers its grid types there; a grid
// crosses as the same openvdb::FloatGrid::Ptr, shared by both sides.
#pragma once

#include <openvdb/openvdb.h>
#include <pybind11/pybind11.h>

namespace levelfuse::python {

namespace py = pybind11;

/// The grid as a pyopenvdb.FloatGrid sharing it; ImportError with a hint if
/// pyopenvdb cannot be imported.
py::object toPyOpenVdb(openvdb::FloatGrid::Ptr grid);
/// The grid a pyopenvdb.FloatGrid holds, or null if `value` is none.
openvdb::FloatGrid::Ptr fromPyOpenVdb(const py::handle& value);
/// The grid as a pyopenvdb.FloatGrid where pyopenvdb can be imported, else as
/// a levelfuse.Grid.
py::object gridForPython(openvdb::FloatGrid::Ptr grid);
/// A colour grid as a pyopenvdb.Vec3SGrid sharing it, None for none;
/// ImportError with a hint if pyopenvdb cannot be imported.
py::object colourForPython(openvdb::Vec3fGrid::Ptr grid);
/// A levelfuse.Grid or a pyopenvdb.FloatGrid argument; TypeError otherwise.
openvdb::FloatGrid::Ptr gridFrom(const py::handle& value, const std::string& name);

}  // namespace levelfuse::python

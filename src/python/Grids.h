// levelfuse Python module: grids as the bytes of a .vdb file.
#pragma once

#include <openvdb/openvdb.h>
#include <pybind11/pybind11.h>

namespace levelfuse::python {

namespace py = pybind11;

/// The bytes io::writeVdb writes for `grids` (the same grids, the same bytes).
py::bytes vdbBytes(const openvdb::GridCPtrVec& grids);

}  // namespace levelfuse::python

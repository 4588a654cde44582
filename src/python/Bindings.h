// levelfuse Python module: what each part of the module binds.
#pragma once

#include <pybind11/pybind11.h>

namespace levelfuse::python {

namespace py = pybind11;

void bindErrors(py::module_& m);          ///< Errors.cc
void bindGrids(py::module_& m);           ///< GridBindings.cc
void bindScans(py::module_& m);           ///< ScanBindings.cc
void bindResult(py::module_& m);          ///< ResultBindings.cc
void bindReconstruction(py::module_& m);  ///< ReconstructionBindings.cc
void bindFusion(py::module_& m);          ///< FusionBindings.cc
void bindEngine(py::module_& m);          ///< EngineBindings.cc

}  // namespace levelfuse::python

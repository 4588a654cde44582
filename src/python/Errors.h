// levelfuse Python module: the exceptions levelfuse raises.
#pragma once

#include <pybind11/pybind11.h>

namespace levelfuse::python {

/// levelfuse.InputError (a ValueError): bad input, naming the file.
PyObject* inputErrorType();
/// levelfuse.Cancelled: a progress callback returned False.
PyObject* cancelledType();

}  // namespace levelfuse::python

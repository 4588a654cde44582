// levelfuse Python module: C++ exceptions become Python exceptions with the
// same message: InputError (a ValueError) for bad input, InsufficientMemory
// (a MemoryError), Cancelled when a progress callback stops the work;
// std::invalid_argument is pybind11's ValueError and std::runtime_error its
// RuntimeError.

#include "Bindings.h"

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/recon/Reconstructor.h>

namespace levelfuse::python {

void bindErrors(py::module_& m) {
  // Registered from the most general: pybind11 asks the latest registered first.
  py::register_exception<Interrupted>(m, "Cancelled", PyExc_Exception);
  py::register_exception<InsufficientMemory>(m, "InsufficientMemory", PyExc_MemoryError);
  py::register_exception<io::InputError>(m, "InputError", PyExc_ValueError);
  m.attr("Cancelled").attr("__doc__") = "The work was stopped: a progress callback returned False.";
  m.attr("InsufficientMemory").attr("__doc__") =
      "The reconstruction would need more memory than the machine has; the message says which voxel size would fit.";
  m.attr("InputError").attr("__doc__") = "Bad input: the message names the file (or argument) and what is wrong.";
}

}  // namespace levelfuse::python

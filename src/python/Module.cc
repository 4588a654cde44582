// levelfuse Python module: range maps from numpy, the MAP reconstruction,
// OpenVDB level sets and meshes back.

#include "Bindings.h"

#include <levelfuse/Version.h>

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>

#include <memory>

namespace levelfuse::python {
namespace {

std::unique_ptr<tbb::global_control> gThreadLimit;

void setThreads(int threads) {
  if (threads < 0) throw py::value_error("set_threads: the number of threads must be 0 (all cores) or more");
  gThreadLimit.reset();
  if (threads > 0)
    gThreadLimit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<std::size_t>(threads));
}

}  // namespace

PYBIND11_MODULE(levelfuse, m) {
  openvdb::initialize();
  m.doc() =
      "levelfuse: surfaces from registered range data (laser scans, depth cameras) by the MAP level-set "
      "method of Whitaker (1998), on OpenVDB.";
  m.attr("__version__") = LEVELFUSE_VERSION_STRING;
  m.def("set_threads", &setThreads, py::arg("threads"),
        "Limit levelfuse (and OpenVDB) to this many threads; 0 uses every core. Results are the same "
        "whatever the number.");
  bindErrors(m);
  bindGrids(m);
  bindScans(m);
  bindResult(m);
  bindReconstruction(m);
  bindFusion(m);
  bindEngine(m);
}

}  // namespace levelfuse::python

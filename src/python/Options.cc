// levelfuse Python module: keyword arguments as a reconstruction's and the readers' options.

#include "Options.h"

#include "Arrays.h"

#include <pybind11/stl.h>

#include <algorithm>

namespace levelfuse::python {
namespace {

/// Removes `key` from `kwargs` and returns its value as T, if it is given and not None.
template <typename T>
std::optional<T> take(py::dict& kwargs, const char* key) {
  if (!kwargs.contains(key)) return std::nullopt;
  const py::object value = kwargs[key];
  PyDict_DelItemString(kwargs.ptr(), key);
  if (value.is_none()) return std::nullopt;
  if constexpr (std::is_same_v<T, int>) {
    if (!py::isinstance<py::int_>(value) || py::isinstance<py::bool_>(value))
      throw py::type_error(std::string(key) + " must be an integer");
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!py::isinstance<py::bool_>(value)) throw py::type_error(std::string(key) + " must be True or False");
  }
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(key) + " has the wrong type (" +
                         py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() + ")");
  }
}

template <typename T>
void takeInto(py::dict& kwargs, const char* key, T& into) {
  if (auto v = take<T>(kwargs, key)) into = *v;
}

DataTermSource dataTermFrom(const std::string& name) {
  if (name == "auto") return DataTermSource::kAuto;
  if (name == "per_map") return DataTermSource::kPerMap;
  if (name == "grids") return DataTermSource::kGrids;
  throw py::value_error("data_term must be 'auto', 'per_map' or 'grids', not '" + name + "'");
}

/// The memory_budget keyword: bytes levelfuse may use (the machine's if left out).
MemoryBudget takeMemoryBudget(py::dict& kwargs) {
  const std::optional<double> bytes = take<double>(kwargs, "memory_budget");
  if (!bytes) return MemoryBudget();
  if (!(*bytes >= 1.0) || !(*bytes < 1.8e19))
    throw py::value_error("memory_budget must be a number of bytes, at least 1");
  return MemoryBudget(static_cast<std::uint64_t>(*bytes));
}

}  // namespace

io::ScanLoadOptions takeLoadOptions(py::dict& kwargs) {
  io::ScanLoadOptions load;
  load.memoryBudget = takeMemoryBudget(kwargs);
  if (auto toward = take<py::object>(kwargs, "toward_scanner"))
    load.stanford.towardScanner = vec3From(*toward, "toward_scanner");
  if (auto sigma = take<double>(kwargs, "sigma")) load.setSigma(numberFrom(py::float_(*sigma), "sigma", true));
  // The readers check these values and name the input they were given for.
  takeInto(kwargs, "depth_scale", load.depthScale);
  takeInto(kwargs, "max_depth", load.maxDepth);
  takeInto(kwargs, "frame_stride", load.frameStride);
  takeInto(kwargs, "pose_time_tolerance", load.poseTimeTolerance);
  return load;
}

ReconstructionOptions takeReconstructionOptions(py::dict& kwargs) {
  ReconstructionOptions o;
  o.memoryBudget = takeMemoryBudget(kwargs);
  o.voxelSize = take<double>(kwargs, "voxel_size");
  o.levels = take<int>(kwargs, "levels");
  o.beta = take<double>(kwargs, "beta");
  o.epsilon = take<double>(kwargs, "epsilon");
  if (auto w = take<std::string>(kwargs, "window")) o.window = windowKindFromName(*w);
  if (auto d = take<std::string>(kwargs, "data_term")) o.dataTerm = dataTermFrom(*d);
  takeInto(kwargs, "tolerance", o.tolerance);
  takeInto(kwargs, "patience", o.patience);
  takeInto(kwargs, "drift", o.drift);
  const std::optional<int> minIterations = take<int>(kwargs, "min_iterations");
  takeInto(kwargs, "max_iterations", o.maxIterations);
  // As the converter does: a limit below the default minimum lowers the minimum.
  o.minIterations = minIterations.value_or(std::min(o.minIterations, o.maxIterations));
  takeInto(kwargs, "name", o.name);
  takeInto(kwargs, "layers", o.engine.layers);
  takeInto(kwargs, "max_step_change", o.engine.maxStepChange);
  takeInto(kwargs, "curvature_step_limit", o.engine.curvatureStepLimit);
  takeInto(kwargs, "stiffness_step_limit", o.engine.stiffnessStepLimit);
  if (auto g = take<int>(kwargs, "grain_size")) {
    if (*g < 0) throw py::value_error("grain_size must be 0 (serial) or more");
    o.engine.grainSize = static_cast<std::size_t>(*g);
  }
  return o;
}

RunSettings takeRunSettings(py::dict& kwargs, std::vector<std::string> inputs) {
  RunSettings s;
  takeInto(kwargs, "linear", s.linear);
  takeInto(kwargs, "fit", s.fit);
  if (auto given = take<std::vector<std::string>>(kwargs, "inputs")) inputs = *given;
  s.inputs = std::move(inputs);
  return s;
}

void refuseUnknownKeywords(const py::dict& kwargs, const std::string& function) {
  for (const auto item : kwargs)
    throw py::type_error(function + "() got an unexpected keyword argument '" + py::str(item.first).cast<std::string>() + "'");
}

}  // namespace levelfuse::python

// levelfuse Python module: keyword arguments as a reconstruction's and the readers' options.
#pragma once

#include "Result.h"

#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/recon/Reconstructor.h>

#include <pybind11/pybind11.h>

namespace levelfuse::python {

namespace py = pybind11;

/// The keywords every reconstruction takes, as in ReconstructionOptions and
/// the converter's options: voxel_size, levels, beta, epsilon, window
/// ('gaussian' or 'binary'), data_term ('auto', 'per_map' or 'grids'),
/// tolerance, patience, drift, min_iterations, max_iterations, name, and the
/// engine's layers, max_step_change, curvature_step_limit,
/// stiffness_step_limit, grain_size, and memory_budget (bytes). Each keyword
/// it reads is removed from `kwargs`; TypeError for a value of the wrong type.
ReconstructionOptions takeReconstructionOptions(py::dict& kwargs);
/// The readers' keywords, as the converter's options: depth_scale (metres per
/// unit of 16-bit depth; 0: the layout's), sigma (the readings' noise),
/// toward_scanner (Stanford scans), max_depth (metres), frame_stride,
/// pose_time_tolerance (TUM folders; seconds), memory_budget (bytes).
/// Removed from `kwargs`.
io::ScanLoadOptions takeLoadOptions(py::dict& kwargs);
/// The run's keywords: linear, fit and inputs (removed from `kwargs`).
RunSettings takeRunSettings(py::dict& kwargs, std::vector<std::string> inputs);
/// TypeError naming the first keyword left in `kwargs`, which `function` does not take.
void refuseUnknownKeywords(const py::dict& kwargs, const std::string& function);

}  // namespace levelfuse::python

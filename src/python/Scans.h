// levelfuse Python module: range maps from numpy and from files.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <pybind11/pybind11.h>

#include <string>

namespace levelfuse::python {

namespace py = pybind11;

/// A depth camera's frame from numpy: `depth` (H, W) float32 in metres (NaN
/// or <= 0: no reading) or uint16 (`depthScale` metres a unit; 0 and 65535:
/// no reading), read straight from the array's buffer; `intrinsics` a 3x3 K
/// or (fx, fy, cx, cy); `pose` 4x4 camera-to-world (column vectors). `sigma`
/// None: the depth camera's noise model; a number: that sigma everywhere; a
/// pair: (minimum, per square metre). Readings deeper than `maxDepth` are dropped.
RangeMap depthFrameFrom(const py::handle& depth, const py::handle& intrinsics, const py::handle& pose,
                        double depthScale, const py::handle& sigma, const py::handle& maxDepth,
                        const std::string& name);

}  // namespace levelfuse::python

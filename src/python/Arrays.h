// levelfuse Python module: numpy arguments checked and converted. Every check
// names the argument: TypeError for a wrong type or dtype, ValueError for a
// wrong shape, a non-contiguous layout or values that cannot be used.
#pragma once

#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>
#include <vector>

namespace levelfuse::python {

namespace py = pybind11;

/// `value` as a numpy array of `dims` dimensions, C-contiguous, without a copy.
py::array requireArray(const py::handle& value, const std::string& name, int dims);
/// True if the array's elements are of type T.
template <typename T>
bool holds(const py::array& a) {
  return a.dtype().num() == py::dtype::of<T>().num();
}
/// A TypeError naming the argument and the dtypes it takes.
py::type_error wrongDtype(const std::string& name, const py::array& a, const std::string& wanted);

/// A 4x4 rigid motion (numpy or nested sequences) in the column-vector
/// convention (the translation in the last column, last row 0 0 0 1), as
/// OpenVDB's row-vector matrix; the same checks as a pose file's.
openvdb::math::Mat4d rigidMotionFrom(const py::handle& value, const std::string& name);
/// OpenVDB's row-vector matrix as a 4x4 numpy array in the column-vector convention.
py::array_t<double> columnVectorMatrix(const openvdb::math::Mat4d& m);
/// A camera's intrinsics: a 3x3 matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]
/// or the four numbers (fx, fy, cx, cy).
PinholeProjection intrinsicsFrom(const py::handle& value, const std::string& name);
/// Three finite numbers.
openvdb::Vec3d vec3From(const py::handle& value, const std::string& name);
/// An (N, 3) array of finite numbers (any real dtype; converted to double).
std::vector<openvdb::Vec3d> pointsFrom(const py::handle& value, const std::string& name);
/// A finite number, positive if `positive`.
double numberFrom(const py::handle& value, const std::string& name, bool positive);
/// (N, 3) float64 array of vectors.
py::array_t<double> numpyPoints(const std::vector<openvdb::Vec3d>& points);

}  // namespace levelfuse::python

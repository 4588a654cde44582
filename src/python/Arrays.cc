// levelfuse Python module: numpy arguments.

#include "Arrays.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/images/DepthImages.h>

#include <cmath>

namespace levelfuse::python {

py::type_error wrongDtype(const std::string& name, const py::array& a, const std::string& wanted) {
  return py::type_error(name + " must be " + wanted + ", not " + py::str(a.dtype()).cast<std::string>());
}

py::array requireArray(const py::handle& value, const std::string& name, int dims) {
  if (!py::isinstance<py::array>(value))
    throw py::type_error(name + " must be a numpy array, not " + py::str(value.get_type().attr("__name__")).cast<std::string>());
  py::array a = py::reinterpret_borrow<py::array>(value);
  if (a.ndim() != dims) {
    std::string shape;
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
    throw py::value_error(name + " must have " + std::to_string(dims) + " dimensions, not shape (" + shape + ")");
  }
  if (!(a.flags() & py::array::c_style))
    throw py::value_error(name + " must be C-contiguous: pass numpy.ascontiguousarray(" + name + ")");
  return a;
}

namespace {

/// Any real array-like of the given shape as doubles (a copy: small arguments only).
py::array_t<double> realArray(const py::handle& value, const std::string& name, std::vector<py::ssize_t> shape) {
  py::array a;
  try {
    a = py::array::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.dtype().kind() == 'O' || a.dtype().kind() == 'U' || a.dtype().kind() == 'S' || a.dtype().kind() == 'c')
    throw py::type_error(name + " must be an array of real numbers");
  py::array_t<double, py::array::c_style | py::array::forcecast> d(a);
  bool same = d.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t i = 0; same && i < shape.size(); ++i) same = shape[i] < 0 || d.shape(static_cast<py::ssize_t>(i)) == shape[i];
  if (!same) {
    std::string want, got;
    for (py::ssize_t s : shape) want += (want.empty() ? "" : ", ") + (s < 0 ? std::string("N") : std::to_string(s));
    for (py::ssize_t i = 0; i < d.ndim(); ++i) got += (i ? ", " : "") + std::to_string(d.shape(i));
    throw py::value_error(name + " must have shape (" + want + "), not (" + got + ")");
  }
  const double* v = d.data();
  for (py::ssize_t i = 0; i < d.size(); ++i)
    if (!std::isfinite(v[i])) throw py::value_error(name + " holds a number that is not finite");
  return d;
}

}  // namespace

openvdb::math::Mat4d rigidMotionFrom(const py::handle& value, const std::string& name) {
  const py::array_t<double> m = realArray(value, name, {4, 4});
  const std::vector<double> rowMajor(m.data(), m.data() + 16);
  try {
    return io::poseFromRowMajor(rowMajor, name, "");
  } catch (const io::InputError& e) {
    throw py::value_error(e.what());
  }
}

py::array_t<double> columnVectorMatrix(const openvdb::math::Mat4d& m) {
  py::array_t<double> out({4, 4});
  auto o = out.mutable_unchecked<2>();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) o(i, j) = m(j, i);
  return out;
}

PinholeProjection intrinsicsFrom(const py::handle& value, const std::string& name) {
  const py::array probe = py::array::ensure(value);
  PinholeProjection p;
  if (probe && probe.ndim() == 1) {
    const py::array_t<double> k = realArray(value, name, {4});
    p = PinholeProjection{k.at(0), k.at(1), k.at(2), k.at(3)};
  } else {
    const py::array_t<double> k = realArray(value, name, {3, 3});
    if (k.at(0, 1) != 0.0 || k.at(1, 0) != 0.0 || k.at(2, 0) != 0.0 || k.at(2, 1) != 0.0 || k.at(2, 2) != 1.0)
      throw py::value_error(name + " must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)");
    p = PinholeProjection{k.at(0, 0), k.at(1, 1), k.at(0, 2), k.at(1, 2)};
  }
  if (!(p.fx > 0.0) || !(p.fy > 0.0)) throw py::value_error(name + ": the focal lengths fx and fy must be positive");
  return p;
}

openvdb::Vec3d vec3From(const py::handle& value, const std::string& name) {
  const py::array_t<double> v = realArray(value, name, {3});
  return openvdb::Vec3d(v.at(0), v.at(1), v.at(2));
}

std::vector<openvdb::Vec3d> pointsFrom(const py::handle& value, const std::string& name) {
  const py::array_t<double> v = realArray(value, name, {-1, 3});
  std::vector<openvdb::Vec3d> points(static_cast<std::size_t>(v.shape(0)));
  const double* d = v.data();
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = openvdb::Vec3d(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
  return points;
}

double numberFrom(const py::handle& value, const std::string& name, bool positive) {
  double x = 0.0;
  try {
    x = py::cast<double>(value);
  } catch (const py::cast_error&) {
    throw py::type_error(name + " must be a number");
  }
  if (!std::isfinite(x) || (positive && !(x > 0.0)))
    throw py::value_error(name + " must be " + (positive ? "a positive, finite number" : "a finite number"));
  return x;
}

py::array_t<double> numpyPoints(const std::vector<openvdb::Vec3d>& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  double* o = out.mutable_data();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a) o[3 * i + a] = points[i][a];
  return out;
}

}  // namespace levelfuse::python

// levelfuse Python module: levelfuse.RangeMap, load_scans and read_depth_png.

#include "Arrays.h"
#include "Bindings.h"
#include "Cancellation.h"
#include "Options.h"
#include "Scans.h"

#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/scan/SphericalScan.h>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace levelfuse::python {
namespace {

/// The noise of a depth camera's readings: None, a sigma, or (minimum, per square metre).
DepthNoise depthNoiseFrom(const py::handle& sigma) {
  if (sigma.is_none()) return DepthNoise{};
  if (py::isinstance<py::tuple>(sigma) || py::isinstance<py::list>(sigma)) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(sigma);
    if (pair.size() != 2) throw py::value_error("sigma must be a number or (minimum, per_square_metre)");
    return DepthNoise{numberFrom(pair[0], "sigma's minimum", true), numberFrom(pair[1], "sigma per square metre", false)};
  }
  return DepthNoise{numberFrom(sigma, "sigma", true), 0.0};
}

double maxDepthFrom(const py::handle& maxDepth) {
  return maxDepth.is_none() ? std::numeric_limits<double>::infinity() : numberFrom(maxDepth, "max_depth", true);
}

/// The depth array's pixels as metres.
io::DepthImage depthImageFrom(const py::handle& value, double depthScale) {
  const py::array depth = requireArray(value, "depth", 2);
  const int height = static_cast<int>(depth.shape(0)), width = static_cast<int>(depth.shape(1));
  if (holds<std::uint16_t>(depth)) {
    if (!(depthScale > 0.0) || !std::isfinite(depthScale))
      throw py::value_error("depth_scale must be a positive number of metres per unit");
    return io::depthImageFromIntegers(width, height, static_cast<const std::uint16_t*>(depth.data()), depthScale);
  }
  if (!holds<float>(depth)) throw wrongDtype("depth", depth, "float32 (metres) or uint16 (depth_scale metres a unit)");
  const float* d = static_cast<const float*>(depth.data());
  io::DepthImage image;
  image.width = width;
  image.height = height;
  image.depth.assign(d, d + static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (float& z : image.depth)
    if (std::isinf(z)) throw py::value_error("depth holds an infinite value (NaN or 0 mean no reading)");
  return image;
}

constexpr double kRadians = M_PI / 180.0;

/// A laser scanner's noise: `sigma`, and more per metre of range if `perMetre` > 0.
DepthNoise rangeNoiseFrom(double sigma, double perMetre) {
  numberFrom(py::float_(sigma), "sigma", true);
  if (!(perMetre >= 0.0) || !std::isfinite(perMetre))
    throw py::value_error("sigma_per_metre must be finite and not negative");
  return DepthNoise{sigma, 0.0, perMetre};
}

/// Two finite numbers (degrees), as a start and a step.
std::pair<double, double> startAndStepFrom(const py::handle& value, const std::string& name) {
  const auto pair = py::cast<std::pair<double, double>>(value);
  if (!std::isfinite(pair.first) || !std::isfinite(pair.second))
    throw py::value_error(name + " must be two finite numbers (start, step) in degrees");
  return pair;
}

/// Rows spaced unevenly (a LiDAR's lasers): their elevations in degrees,
/// lowest first, in radians. Their order is checked where they are used
/// (RangeMap::spherical, stepsOnRows), whose std::invalid_argument Python
/// sees as ValueError.
std::vector<double> rowElevationsFrom(const py::handle& value, const std::string& name) {
  std::vector<double> rows;
  try {
    rows = py::cast<std::vector<double>>(value);
  } catch (const py::cast_error&) {
    throw py::type_error(name + " must be numbers (degrees)");
  }
  for (double& elevation : rows) elevation *= kRadians;
  return rows;
}

/// A grid's rows from `elevation`: (start, step), or one elevation per row.
void setRowsFrom(SphericalProjection& grid, const py::handle& elevation) {
  if (py::len(elevation) != 2) {
    grid.rowElevations = rowElevationsFrom(elevation, "elevation");
    return;
  }
  const auto [start, step] = startAndStepFrom(elevation, "elevation");
  grid.elevationStart = start * kRadians;
  grid.elevationStep = step * kRadians;
}

RangeMap sphericalMapFrom(const py::handle& ranges, const py::handle& azimuth, const py::handle& elevation,
                          const py::handle& pose, double sigma, double sigmaPerMetre, const std::string& name) {
  const py::array r = requireArray(ranges, "ranges", 2);
  if (!holds<float>(r)) throw wrongDtype("ranges", r, "float32 (world units)");
  const float* d = static_cast<const float*>(r.data());
  std::vector<float> values(d, d + r.size());
  const auto [azimuthStart, azimuthStep] = startAndStepFrom(azimuth, "azimuth");
  SphericalProjection grid;
  grid.azimuthStart = azimuthStart * kRadians;
  grid.azimuthStep = azimuthStep * kRadians;
  setRowsFrom(grid, elevation);
  const openvdb::math::Mat4d scannerToWorld = rigidMotionFrom(pose, "pose");
  const DepthNoise noise = rangeNoiseFrom(sigma, sigmaPerMetre);
  py::gil_scoped_release released;
  return RangeMap::spherical(static_cast<int>(r.shape(1)), static_cast<int>(r.shape(0)), std::move(values), grid,
                             scannerToWorld, noise, name);
}

/// A scanner's steps: `elevationStep` a number of degrees, or the elevations
/// of its lasers (uneven rows; the step is then their finest spacing).
AngularSteps stepsFrom(double azimuthStep, const py::handle& elevationStep) {
  const double azimuth = numberFrom(py::float_(azimuthStep), "azimuth_step", true) * kRadians;
  if (!py::isinstance<py::sequence>(elevationStep) && !py::isinstance<py::array>(elevationStep))
    return AngularSteps{azimuth, numberFrom(elevationStep, "elevation_step", true) * kRadians};
  return stepsOnRows(azimuth, rowElevationsFrom(elevationStep, "elevation_step"), "elevation_step");
}

RangeMap sphericalMapOfPoints(const py::handle& points, double azimuthStep, const py::handle& elevationStep,
                              const py::handle& pose, double sigma, double sigmaPerMetre, const std::string& name) {
  const std::vector<openvdb::Vec3d> scannerPoints = pointsFrom(points, "points");
  const AngularSteps steps = stepsFrom(azimuthStep, elevationStep);
  const openvdb::math::Mat4d scannerToWorld = rigidMotionFrom(pose, "pose");
  const DepthNoise noise = rangeNoiseFrom(sigma, sigmaPerMetre);
  py::gil_scoped_release released;
  return sphericalMapFromPoints(scannerPoints, steps, scannerToWorld, noise, name);
}

}  // namespace

RangeMap depthFrameFrom(const py::handle& depth, const py::handle& intrinsics, const py::handle& pose,
                        double depthScale, const py::handle& sigma, const py::handle& maxDepth,
                        const std::string& name) {
  io::DepthImage image = depthImageFrom(depth, depthScale);
  const PinholeProjection k = intrinsicsFrom(intrinsics, "K");
  const openvdb::math::Mat4d cameraToWorld = rigidMotionFrom(pose, "pose");
  const DepthNoise noise = depthNoiseFrom(sigma);
  const double deepest = maxDepthFrom(maxDepth);
  py::gil_scoped_release released;
  if (std::isfinite(deepest)) io::dropReadingsBeyond(image, deepest);
  return io::depthFrame(std::move(image), k, cameraToWorld, noise, name);
}

namespace {

RangeMap orthographicMapFrom(const py::handle& readings, double pixelSize, const py::handle& pose, double sigma,
                             const py::handle& origin, const std::string& name) {
  const py::array r = requireArray(readings, "readings", 2);
  if (!holds<float>(r)) throw wrongDtype("readings", r, "float32 (world units)");
  const float* d = static_cast<const float*>(r.data());
  std::vector<float> values(d, d + r.size());
  const openvdb::math::Mat4d mapToWorld = rigidMotionFrom(pose, "pose");
  const openvdb::Vec3d o = origin.is_none() ? openvdb::Vec3d(0.0) : vec3From(origin, "origin");
  const OrthographicProjection p{numberFrom(py::float_(pixelSize), "pixel_size", true), {o.x(), o.y()}};
  numberFrom(py::float_(sigma), "sigma", true);
  py::gil_scoped_release released;
  return RangeMap::orthographic(static_cast<int>(r.shape(1)), static_cast<int>(r.shape(0)), std::move(values), p,
                                mapToWorld, sigma, name);
}

/// A spherical map's row elevations in degrees where its rows are spaced unevenly.
std::vector<double> rowElevationsInDegrees(const RangeMap& r) {
  std::vector<double> degrees;
  // Empty but for a spherical map's uneven rows.
  for (const double elevation : r.sphericalProjection().rowElevations) degrees.push_back(elevation / kRadians);
  return degrees;
}

py::tuple scannerPositionOf(const RangeMap& r) {
  const openvdb::Vec3d p = r.scannerPosition();
  return py::make_tuple(p.x(), p.y(), p.z());
}

py::array_t<float> readingsOf(const RangeMap& r) {
  py::array_t<float> out({static_cast<py::ssize_t>(r.height()), static_cast<py::ssize_t>(r.width())});
  auto o = out.mutable_unchecked<2>();
  for (int v = 0; v < r.height(); ++v)
    for (int u = 0; u < r.width(); ++u) o(v, u) = r.reading(u, v);
  return out;
}

std::string rangeMapRepr(const RangeMap& r) {
  return "<levelfuse.RangeMap '" + r.name() + "': " + projectionName(r.kind()) + ", " + std::to_string(r.width()) +
         " x " + std::to_string(r.height()) + ", " + std::to_string(r.validCount()) + " readings>";
}

/// RangeMap's static constructors: pinhole, orthographic, spherical and from_points.
void defineRangeMapConstructors(py::class_<RangeMap>& rangeMap) {
  rangeMap
      .def_static("pinhole", &depthFrameFrom, py::arg("depth"), py::arg("K"), py::arg("pose"),
                  py::arg("depth_scale") = 0.001, py::arg("sigma") = py::none(), py::arg("max_depth") = py::none(),
                  py::arg("name") = "",
                  "A depth camera's frame. depth: (H, W) float32 metres (NaN or <= 0: no reading) or uint16 "
                  "(depth_scale metres a unit, 0.001 by default; 0 and 65535: no reading). K: 3x3 intrinsics or "
                  "(fx, fy, cx, cy). pose: 4x4 camera-to-world, column vectors (x right, y down, z forward; "
                  "Open3D's extrinsic is its inverse). sigma: None for the depth camera's noise model "
                  "max(1 mm, 1.5 mm z^2), a number for one sigma, or (minimum, per_square_metre).")
      .def_static("orthographic", &orthographicMapFrom, py::arg("readings"), py::arg("pixel_size"), py::arg("pose"),
                  py::arg("sigma"), py::arg("origin") = py::none(), py::arg("name") = "",
                  "A scan of parallel rays along +z of its frame: readings (H, W) float32, world units along the "
                  "rays (NaN: no reading); pixel_size between rays; pose 4x4 map-to-world (column vectors); origin "
                  "(x, y, unused z) of pixel (0, 0) in the map's frame.")
      .def_static("spherical", &sphericalMapFrom, py::arg("ranges"), py::arg("azimuth"), py::arg("elevation"),
                  py::arg("pose"), py::arg("sigma"), py::arg("sigma_per_metre") = 0.0, py::arg("name") = "",
                  "A scan on a spherical scanner's grid: ranges (H, W) float32, distances from the scanner in world "
                  "units (NaN or <= 0: no return), a row per elevation and a column per azimuth. azimuth, "
                  "elevation: (start, step) in degrees; azimuth about the scanner's z axis (up) from its x axis, "
                  "elevation from its xy plane. elevation may instead hold one elevation per row (H of them, "
                  "increasing: rows spaced unevenly, a LiDAR's lasers). pose: 4x4 scanner-to-world, column vectors. sigma: the noise, at "
                  "least; sigma_per_metre: noise per metre of range (sigma(r) = max(sigma, sigma_per_metre r)).")
      .def_static("from_points", &sphericalMapOfPoints, py::arg("points"), py::arg("azimuth_step"),
                  py::arg("elevation_step"), py::arg("pose"), py::arg("sigma"), py::arg("sigma_per_metre") = 0.0,
                  py::arg("name") = "",
                  "A spherical scan from the points a scanner measured: points (N, 3) in the scanner's frame (z "
                  "up; points at the scanner are no return), binned at the scanner's angular steps (degrees); a "
                  "pixel that several points fall in keeps the nearest. elevation_step may instead hold the "
                  "elevations of the scanner's lasers (degrees, increasing): each point goes to the row nearest "
                  "its elevation. pose, sigma, sigma_per_metre: as for "
                  "spherical().");
}

void bindRangeMap(py::module_& m) {
  py::class_<RangeMap> rangeMap(m, "RangeMap",
                                "A range map: a depth camera's frame (pinhole), a terrestrial laser scanner's or a "
                                "LiDAR's scan (spherical) or a scan of parallel rays (orthographic), registered in "
                                "the world by its pose.");
  defineRangeMapConstructors(rangeMap);
  rangeMap.def_property_readonly("kind", [](const RangeMap& r) { return projectionName(r.kind()); })
      .def_property_readonly(
          "row_elevations", &rowElevationsInDegrees,
          "A spherical map's row elevations (degrees) where its rows are spaced unevenly; empty otherwise.")
      .def_property_readonly("width", &RangeMap::width)
      .def_property_readonly("height", &RangeMap::height)
      .def_property_readonly("name", &RangeMap::name)
      .def_property_readonly("sigma", &RangeMap::sigma, "The map's noise sigma (world units).")
      .def_property_readonly("valid_count", &RangeMap::validCount, "Pixels with a reading.")
      .def_property_readonly("memory_bytes", &RangeMap::memoryBytes)
      .def_property_readonly("pose", [](const RangeMap& r) { return columnVectorMatrix(r.mapToWorld()); },
                             "4x4 map-to-world (camera-to-world), column vectors.")
      .def_property_readonly("scanner_position", &scannerPositionOf)
      .def("readings", &readingsOf,
           "The readings, (H, W) float32 (NaN: none): depths along the optical axis or along parallel rays, "
           "ranges from a spherical scanner.")
      .def("__repr__", &rangeMapRepr);
}

std::vector<RangeMap> loadScansFor(const std::string& path, const py::object& progress, py::kwargs kw) {
  py::dict kwargs(kw);
  io::ScanLoadOptions load = takeLoadOptions(kwargs);
  refuseUnknownKeywords(kwargs, "load_scans");
  Cancellation cancellation;
  ProgressRelay relay(progress, cancellation);
  load.interrupter = cancellation.interrupter();
  load.progress = [&](std::size_t read, std::size_t total) { relay.count("loading", read, total); };
  return runReleased(cancellation, &relay, [&] { return io::loadScans(path, load); });
}

py::array_t<std::uint16_t> readDepthPng(const std::string& path) {
  io::DepthSamples image;
  {
    py::gil_scoped_release released;
    image = io::readDepthPngSamples(path);
  }
  py::array_t<std::uint16_t> out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width)});
  std::copy(image.samples.begin(), image.samples.end(), out.mutable_data());
  return out;
}

/// load_scans and read_depth_png.
void bindScanReaders(py::module_& m) {
  m.def("load_scans", &loadScansFor, py::arg("path"), py::kw_only(), py::arg("progress") = py::none(),
        "The scans at path, as the converter reads them: a Stanford .conf, a PTX or E57 file of terrestrial laser "
        "scans, a JSON manifest (which may also list XYZ and PLY point clouds and KITTI velodyne sweeps with their "
        "sensors' poses), or a folder of depth frames (7-Scenes or TUM RGB-D layout). Keywords, as the converter's "
        "options: depth_scale (metres per unit of 16-bit depth; 0: the layout's), sigma (the readings' noise, world "
        "units; default: estimated, the depth camera's model, or 2 mm for PTX and E57 scans and point clouds), "
        "toward_scanner (Stanford scans' direction to the scanner), max_depth (metres), frame_stride (every n-th "
        "frame), pose_time_tolerance (TUM; seconds), memory_budget (bytes the readers may use; the machine's memory "
        "by default: a scan that would need more raises InputError). progress(dict) is called as scans are read.");
  m.def("read_depth_png", &readDepthPng, py::arg("path"), "A 16-bit depth PNG's samples, (H, W) uint16, unscaled.");
}

}  // namespace

void bindScans(py::module_& m) {
  bindRangeMap(m);
  bindScanReaders(m);
}

}  // namespace levelfuse::python

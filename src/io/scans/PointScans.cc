// levelfuse: point clouds as spherical range maps (see PointScans.h).

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/scans/PointScans.h>
#include <levelfuse/scan/LaserSweep.h>

#include "../FileExtension.h"
#include "GridPixels.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

std::string degrees(double radians) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", radians * 180.0 / M_PI);
  return text;
}

/// Refuses steps finer than kMinCloudStep (the binning counts a turn's
/// columns before it looks at the points) or whose grid over the points would
/// have more than kMaxPixelsPerCloudPoint pixels per point, before either is
/// allocated.
void requireGridOfTheCloudsSize(const std::vector<Vec3d>& points, const AngularSteps& steps,
                                const std::string& path) {
  if (!(std::min(steps.azimuth, steps.elevation) >= kMinCloudStep))
    throw InputError(path, "angular steps of " + degrees(steps.azimuth) + " x " + degrees(steps.elevation) +
                               " degrees are finer than any scanner's (at least " + degrees(kMinCloudStep) +
                               " degrees): are the points a scan's, and the steps the sensor's?");
  const double pixels = gridPixelsAtMost(points, steps);
  if (!(pixels <= kMaxPixelsPerCloudPoint * static_cast<double>(points.size()) + kSpareGridPixels))
    throw InputError(path, "angular steps of " + degrees(steps.azimuth) + " x " + degrees(steps.elevation) +
                               " degrees would bin the " + std::to_string(points.size()) + " points into up to " +
                               std::to_string(static_cast<long long>(std::min(pixels, 1e18))) +
                               " pixels, more than " + std::to_string(static_cast<int>(kMaxPixelsPerCloudPoint)) +
                               " per point: are the steps the sensor's?");
}

}  // namespace

PointCloud readPointCloud(const std::string& path, const Interrupter& interrupter, const MemoryBudget& budget) {
  const std::string extension = detail::lowercaseExtension(path);
  if (extension == ".xyz" || extension == ".txt") return readXyzPoints(path, interrupter);
  if (extension == ".ply") return readPlyPoints(path, budget);
  throw InputError(path, "unknown point file type " + quote(extension) + " (expected .xyz, .txt or .ply)");
}

std::vector<Vec3d> pointsInSensorFrame(const std::vector<Vec3d>& worldPoints,
                                       const openvdb::math::Mat4d& sensorToWorld) {
  const openvdb::math::Mat4d worldToSensor = sensorToWorld.inverse();
  std::vector<Vec3d> sensorPoints;
  sensorPoints.reserve(worldPoints.size());
  for (const Vec3d& p : worldPoints) sensorPoints.push_back(worldToSensor.transform(p));
  return sensorPoints;
}

RangeMap rangeMapFromPointCloud(const std::vector<Vec3d>& sensorPoints, const openvdb::math::Mat4d& sensorToWorld,
                                const std::optional<AngularSteps>& steps, double sigma, const std::string& path,
                                const std::string& name, const std::vector<Rgb8>& colours) {
  try {
    const AngularSteps used = steps ? *steps : estimateAngularSteps(sensorPoints);
    requireGridOfTheCloudsSize(sensorPoints, used, path);
    return sphericalMapFromPoints(sensorPoints, used, sensorToWorld, sigma, name, colours);
  } catch (const std::invalid_argument& e) {  // no steps, or no map
    throw InputError(path, e.what());
  }
}

std::vector<RangeMap> rangeMapsOfSweep(const std::vector<Vec3d>& sensorPoints, const openvdb::math::Mat4d& sensorToWorld,
                                       const std::optional<AngularSteps>& steps, double sigma, const std::string& path,
                                       const std::string& name) {
  if (!steps)
    if (const std::optional<LaserRows> lasers = lasersInFiringOrder(sensorPoints)) {
      try {
        return sweepRangeMaps(sensorPoints, *lasers, sensorToWorld, sigma, name);
      } catch (const std::invalid_argument& e) {
        throw InputError(path, e.what());
      }
    }
  std::vector<RangeMap> maps;
  maps.push_back(rangeMapFromPointCloud(sensorPoints, sensorToWorld, steps, sigma, path, name));
  return maps;
}

}  // namespace levelfuse::io

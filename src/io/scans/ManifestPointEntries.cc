// levelfuse: a manifest's point-cloud entries (see ManifestPointEntries.h).

#include "ManifestPointEntries.h"

#include <levelfuse/io/scans/PointScans.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;
using openvdb::math::Mat4d;

constexpr double kRadians = M_PI / 180.0;
/// The largest frame index a `kitti-bin` entry takes.
constexpr double kMaxFrame = 1e9;

/// The entry's angular step `key` (degrees), in radians: positive, less than half a turn.
double stepOf(const Entry& e, const char* key) {
  const double degrees = e.positive(key, 0.0);
  if (!(degrees < 180.0)) e.fail(std::string("'") + key + "' must be less than 180 degrees");
  return degrees * kRadians;
}

/// The entry's "row_elevations" (degrees, a sensor's lasers), in radians: two
/// or more, strictly between the poles (stepsOnRows checks their order).
std::vector<double> rowElevationsOf(const Entry& e) {
  const auto& rows = e["row_elevations"];
  if (!rows.is_array() || rows.size() < 2)
    e.fail("'row_elevations' needs two or more elevations (degrees, one per laser, lowest first)");
  std::vector<double> elevations = e.numbers(rows, "row_elevations", rows.size());
  for (double& elevation : elevations) {
    if (!(std::fabs(elevation) < 90.0)) e.fail("'row_elevations' must lie strictly between -90 and 90 degrees");
    elevation *= kRadians;
  }
  return elevations;
}

/// The entry's angular steps, if it gives them: "azimuth_step" and either
/// "elevation_step" or "row_elevations" (uneven rows: stepsOnRows).
std::optional<AngularSteps> stepsOf(const Entry& e) {
  if (e.has("row_elevations")) {
    if (e.has("elevation_step")) e.fail("give 'elevation_step' or 'row_elevations', not both");
    if (!e.has("azimuth_step")) e.fail("'row_elevations' needs the 'azimuth_step' (degrees) beside it");
    std::vector<double> rows = rowElevationsOf(e);
    const double azimuthStep = stepOf(e, "azimuth_step");
    return e.checked([&] { return stepsOnRows(azimuthStep, std::move(rows), "'row_elevations'"); });
  }
  const int given = e.countOf({"azimuth_step", "elevation_step"});
  if (given == 0) return std::nullopt;
  if (given == 1)
    e.fail("give both 'azimuth_step' and 'elevation_step' (degrees), or neither (then they are estimated from the "
           "points)");
  return AngularSteps{stepOf(e, "azimuth_step"), stepOf(e, "elevation_step")};
}

/// The sensor's pose from its "origin" (its axes the world's) or its "pose"
/// or "pose_file": exactly one of them.
Mat4d sensorPoseOf(const Entry& e) {
  const int given = e.countOf({"origin", "pose", "pose_file"});
  if (given == 0) e.fail("missing the sensor's 'origin' [x, y, z] or its 'pose' (or 'pose_file')");
  if (given > 1) e.fail("give one of the sensor's 'origin', 'pose' and 'pose_file', not " + std::to_string(given));
  if (!e.has("origin")) return poseOf(e, e.manifest());
  const std::vector<double> origin = e.numbers("origin", 3);
  Mat4d pose = Mat4d::identity();
  pose.setTranslation(Vec3d(origin[0], origin[1], origin[2]));
  return pose;
}

/// Whether the entry's points are in the world (its "coordinates").
bool pointsInWorld(const Entry& e) {
  if (!e.has("coordinates")) return true;
  const std::string coordinates = e.string("coordinates");
  if (coordinates != "world" && coordinates != "sensor")
    e.fail("'coordinates' must be \"world\" or \"sensor\", not " + quote(coordinates));
  return coordinates == "world";
}

/// Frame "frame" of KITTI odometry's "poses" with the "calib" file's Tr: the velodyne's pose.
Mat4d kittiOdometryPoseOf(const Entry& e) {
  for (const char* key : {"poses", "calib", "frame"})
    if (!e.has(key))
      e.fail(std::string("missing '") + key + "': KITTI odometry's poses need 'poses', 'calib' and 'frame'");
  const double frame = e.number("frame", 0.0);
  if (frame < 0.0 || frame > kMaxFrame || frame != std::floor(frame))
    e.fail("'frame' must be a whole number from 0 (the first line of 'poses')");
  const std::string poses = e.path("poses"), calib = e.path("calib");
  return kittiVelodyneToWorld(readKittiCameraToWorld(poses, static_cast<long long>(frame)),
                              readKittiVelodyneToCamera(calib));
}

/// The velodyne's pose: its "pose" (or "pose_file"), or KITTI odometry's.
Mat4d velodynePoseOf(const Entry& e) {
  const int direct = e.countOf({"pose", "pose_file"}), odometry = e.countOf({"poses", "calib", "frame"});
  if (direct > 0 && odometry > 0)
    e.fail("give the velodyne's 'pose' (or 'pose_file') or KITTI odometry's 'poses', 'calib' and 'frame', not both");
  if (direct > 1) e.fail("give the velodyne's 'pose' or its 'pose_file', not both");
  if (direct == 1) return poseOf(e, e.manifest());
  if (odometry == 0)
    e.fail("missing the velodyne's 'pose' (or 'pose_file'), or KITTI odometry's 'poses', 'calib' and 'frame'");
  return kittiOdometryPoseOf(e);
}

std::string fileName(const std::string& path) { return std::filesystem::path(path).filename().string(); }

}  // namespace

RangeMap loadPointsEntry(const Entry& e, const ScanLoadOptions& defaults) {
  e.requireOnly({"format", "file", "origin", "pose", "pose_file", "coordinates", "azimuth_step", "elevation_step",
                 "row_elevations", "sigma", "misses_are_empty", "dropout_reach"});
  const std::string file = e.path("file");
  const Mat4d sensorToWorld = sensorPoseOf(e);
  const bool inWorld = pointsInWorld(e);
  const std::optional<AngularSteps> steps = stepsOf(e);
  const double sigma = e.positive("sigma", defaults.pointSigma);
  PointCloud cloud = readPointCloud(file, defaults.interrupter, defaults.memoryBudget);
  const std::vector<Vec3d> sensorPoints =
      inWorld ? pointsInSensorFrame(cloud.points, sensorToWorld) : std::move(cloud.points);
  return rangeMapFromPointCloud(sensorPoints, sensorToWorld, steps, sigma, file, fileName(file), cloud.colours);
}

std::vector<RangeMap> loadKittiBinEntry(const Entry& e, const ScanLoadOptions& defaults) {
  e.requireOnly({"format", "file", "pose", "pose_file", "poses", "calib", "frame", "azimuth_step", "elevation_step",
                 "row_elevations", "sigma", "misses_are_empty", "dropout_reach"});
  const std::string file = e.path("file");
  const Mat4d velodyneToWorld = velodynePoseOf(e);
  const std::optional<AngularSteps> steps = stepsOf(e);
  const double sigma = e.positive("sigma", defaults.pointSigma);
  return rangeMapsOfSweep(readKittiBin(file, defaults.memoryBudget).points, velodyneToWorld, steps, sigma, file, fileName(file));
}

}  // namespace levelfuse::io

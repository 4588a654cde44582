#include "support/DepthFolders.h"

#include "support/Files.h"

#include <openvdb/math/Mat3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace levelfuse::test {

namespace fs = std::filesystem;
using openvdb::Vec3d;

namespace {

/// R(q) p for a unit quaternion (x, y, z, w).
Vec3d rotate(const openvdb::math::Quatd& q, const Vec3d& p) {
  const Vec3d u(q.x(), q.y(), q.z());
  const double w = q.w();
  return p + 2.0 * w * u.cross(p) + 2.0 * u.cross(u.cross(p));
}

std::string number(double v, const char* format = "%.6f") {
  char text[64];
  std::snprintf(text, sizeof(text), format, v);
  return text;
}

std::vector<std::uint16_t> quantised(const std::vector<double>& depths, double unitsPerMetre) {
  std::vector<std::uint16_t> samples;
  for (double d : depths) samples.push_back(static_cast<std::uint16_t>(std::lround(d * unitsPerMetre)));
  return samples;
}

std::string intrinsicsText(const PinholeProjection& k) {
  return number(k.fx) + " 0 " + number(k.cx) + "\n0 " + number(k.fy) + " " + number(k.cy) + "\n0 0 1\n";
}

}  // namespace

openvdb::math::Quatd rotationAbout(const Vec3d& axis, double degrees) {
  const double half = degrees * M_PI / 360.0;
  const Vec3d a = axis.unitSafe() * std::sin(half);
  return openvdb::math::Quatd(a.x(), a.y(), a.z(), std::cos(half));
}

std::vector<double> renderPlane(const CameraPose& pose, const PinholeProjection& k, int width, int height,
                                double planeZ) {
  std::vector<double> depths;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) {
      const Vec3d ray = rotate(pose.rotation, Vec3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0));
      const double z = ray.z() != 0.0 ? (planeZ - pose.position.z()) / ray.z() : -1.0;
      depths.push_back(z > 0.0 ? z : 0.0);  // the ray's z component in the camera is 1: s is the depth
    }
  return depths;
}

double farthestFromPlane(const RangeMap& map, double planeZ) {
  double worst = 0.0;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      if (map.valid(u, v)) worst = std::max(worst, std::fabs(map.readingPoint(u, v).z() - planeZ));
  return worst;
}

void writeTumFolder(const std::string& folder, const TumFixture& f) {
  fs::create_directories(fs::path(folder) / "depth");
  std::ostringstream trajectory, list;
  trajectory << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
  for (const TumFixture::Pose& p : f.poses) {
    const auto& q = p.pose.rotation;
    trajectory << number(p.time, "%.4f");
    for (double v : {p.pose.position.x(), p.pose.position.y(), p.pose.position.z(), q.x(), q.y(), q.z(), q.w()})
      trajectory << " " << number(v, "%.9f");
    trajectory << "\n";
  }
  list << "# depth maps\n# timestamp filename\n";
  for (double time : f.frameTimes) {
    const TumFixture::Pose* nearest = &f.poses.front();
    for (const TumFixture::Pose& p : f.poses)
      if (std::fabs(p.time - time) < std::fabs(nearest->time - time)) nearest = &p;
    const std::string name = "depth/" + number(time) + ".png";
    list << number(time) << " " << name << "\n";
    writePng((fs::path(folder) / name).string(), f.width, f.height, 16, 1,
             quantised(renderPlane(nearest->pose, f.intrinsics, f.width, f.height, f.planeZ), 5000.0));
  }
  writeText((fs::path(folder) / "groundtruth.txt").string(), trajectory.str());
  writeText((fs::path(folder) / "depth.txt").string(), list.str());
  if (f.writeIntrinsics) writeText((fs::path(folder) / "camera-intrinsics.txt").string(), intrinsicsText(f.intrinsics));
}

void writeSevenScenesFolder(const std::string& folder, const std::vector<CameraPose>& poses,
                            const PinholeProjection& k, int width, int height, double planeZ) {
  fs::create_directories(folder);
  writeText((fs::path(folder) / "camera-intrinsics.txt").string(), intrinsicsText(k));
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const std::string stem = (fs::path(folder) / ("frame-" + number(double(i), "%06.0f"))).string();
    writePng(stem + ".depth.png", width, height, 16, 1,
             quantised(renderPlane(poses[i], k, width, height, planeZ), 1000.0));
    // The rotation's columns are the camera's axes in the world.
    const Vec3d x = rotate(poses[i].rotation, Vec3d(1, 0, 0)), y = rotate(poses[i].rotation, Vec3d(0, 1, 0)),
                z = rotate(poses[i].rotation, Vec3d(0, 0, 1)), t = poses[i].position;
    std::ostringstream pose;
    for (int r = 0; r < 3; ++r)
      pose << number(x[r], "%.9f") << " " << number(y[r], "%.9f") << " " << number(z[r], "%.9f") << " "
           << number(t[r], "%.9f") << "\n";
    pose << "0 0 0 1\n";
    writeText(stem + ".pose.txt", pose.str());
  }
}

}  // namespace levelfuse::test

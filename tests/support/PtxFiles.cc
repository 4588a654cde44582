// PTX files for tests.

#include "support/PtxFiles.h"

#include <cmath>
#include <cstdio>

namespace levelfuse::test {

namespace {

using openvdb::Vec3d;

std::string numbers(std::initializer_list<double> values) {
  std::string line;
  char text[64];
  for (const double v : values) {
    std::snprintf(text, sizeof(text), "%.9f", v);
    line += (line.empty() ? "" : " ") + std::string(text);
  }
  return line + "\n";
}

std::string matrixRows(const openvdb::math::Mat4d& m) {
  std::string text;
  for (int row = 0; row < 4; ++row) text += numbers({m(row, 0), m(row, 1), m(row, 2), m(row, 3)});
  return text;
}

}  // namespace

openvdb::math::Mat4d turnedScanner() {
  const double c = std::cos(M_PI / 6.0), s = std::sin(M_PI / 6.0);
  return openvdb::math::Mat4d(c, s, 0.0, 0.0, -s, c, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 3.0, 1.0);
}

PtxGrid turnedGrid() {
  PtxGrid grid;
  grid.scannerToWorld = turnedScanner();
  return grid;
}

openvdb::math::Mat4d scannerLookingAt(const Vec3d& position, const Vec3d& target) {
  Vec3d forward = target - position;
  forward.z() = 0.0;
  forward.normalize();
  const Vec3d up(0.0, 0.0, 1.0);
  const Vec3d left = up.cross(forward);
  return openvdb::math::Mat4d(forward.x(), forward.y(), 0.0, 0.0, left.x(), left.y(), 0.0, 0.0, 0.0, 0.0, 1.0, 0.0,
                              position.x(), position.y(), position.z(), 1.0);
}

Vec3d ptxRay(const PtxGrid& grid, int c, int r) {
  const double azimuth = grid.azimuthStart + c * grid.azimuthStep;
  const double elevation = grid.elevationStart + r * grid.elevationStep;
  return Vec3d(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
}

RangeAlong sphere(const Vec3d& centre, double radius) {
  return [=](const Vec3d& ray) {
    const double along = ray.dot(centre);
    const double discriminant = along * along - centre.lengthSqr() + radius * radius;
    if (discriminant < 0.0) return -1.0;
    const double nearer = along - std::sqrt(discriminant);
    return nearer > 0.0 ? nearer : along + std::sqrt(discriminant);
  };
}

RangeAlong plane(const Vec3d& normal, double offset) {
  return [=](const Vec3d& ray) {
    const double facing = normal.dot(ray);
    return facing > 1e-9 ? offset / facing : -1.0;
  };
}

RangeAlong stationSphere() { return sphere(kStationSphereCentre, kStationSphereRadius); }

double farthestFromStationSphere(const RangeMap& map, const openvdb::math::Mat4d& scannerToWorld) {
  const Vec3d centre = scannerToWorld.transform(kStationSphereCentre);
  double farthest = 0.0;
  for (int v = 0; v < map.height(); ++v)
    for (int u = 0; u < map.width(); ++u)
      if (map.valid(u, v))
        farthest = std::max(farthest, std::fabs((map.readingPoint(u, v) - centre).length() - kStationSphereRadius));
  return farthest;
}

std::vector<Vec3d> scanPoints(const PtxGrid& grid, const RangeAlong& range) {
  std::vector<Vec3d> points;
  for (int c = 0; c < grid.columns; ++c)
    for (int r = 0; r < grid.rows; ++r) {
      const Vec3d ray = ptxRay(grid, c, r);
      const double distance = range(ray);
      points.push_back(distance > 0.0 ? ray * distance : Vec3d(0.0));
    }
  return points;
}

std::string ptxScanText(const PtxGrid& grid, const std::vector<Vec3d>& scannerPoints, PtxFrame frame,
                        bool colours) {
  const openvdb::math::Mat4d& pose = grid.scannerToWorld;
  std::string text = std::to_string(grid.columns) + "\n" + std::to_string(grid.rows) + "\n";
  text += numbers({pose(3, 0), pose(3, 1), pose(3, 2)});
  for (int axis = 0; axis < 3; ++axis) text += numbers({pose(axis, 0), pose(axis, 1), pose(axis, 2)});
  text += matrixRows(frame == PtxFrame::kScanner ? pose : openvdb::math::Mat4d::identity());
  for (std::size_t i = 0; i < scannerPoints.size(); ++i) {
    const Vec3d& p = scannerPoints[i];
    const bool miss = p == Vec3d(0.0);
    const Vec3d written = miss || frame == PtxFrame::kScanner ? p : pose.transform(p);
    std::string line = numbers({written.x(), written.y(), written.z(), 0.5});
    if (colours) {
      line.pop_back();
      line += " " + std::to_string(i * 7 % 256) + " " + std::to_string(i * 11 % 256) + " 200\n";
    }
    text += line;
  }
  return text;
}

}  // namespace levelfuse::test

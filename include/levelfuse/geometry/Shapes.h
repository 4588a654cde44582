// levelfuse: analytic shapes and their signed distance functions.
//
// Signed distance in world units, negative inside (OpenVDB's convention). The
// sphere, torus and box distances are exact; unions are exact outside and a
// bound inside. All are 1-Lipschitz, which the samplers rely on.
#pragma once

#include <openvdb/Types.h>

#include <algorithm>
#include <cmath>

namespace levelfuse::shapes {

using openvdb::Vec3d;

struct Sphere {
  Vec3d centre{0.0};
  double radius = 1.0;
  double operator()(const Vec3d& p) const { return (p - centre).length() - radius; }
};

/// A torus around the z axis through `centre`: tube of radius `minor` around a
/// circle of radius `major`.
struct Torus {
  Vec3d centre{0.0};
  double major = 2.0;
  double minor = 0.5;
  double operator()(const Vec3d& p) const {
    const Vec3d q = p - centre;
    const double ring = std::sqrt(q.x() * q.x() + q.y() * q.y()) - major;
    return std::sqrt(ring * ring + q.z() * q.z()) - minor;
  }
};

/// An axis-aligned box with half extents `half`.
struct Box {
  Vec3d centre{0.0};
  Vec3d half{1.0};
  double operator()(const Vec3d& p) const {
    const Vec3d q = p - centre;
    const Vec3d d(std::fabs(q.x()) - half.x(), std::fabs(q.y()) - half.y(), std::fabs(q.z()) - half.z());
    const Vec3d outside(std::max(d.x(), 0.0), std::max(d.y(), 0.0), std::max(d.z(), 0.0));
    return outside.length() + std::min(std::max(d.x(), std::max(d.y(), d.z())), 0.0);
  }
};

/// A segment from a to b thickened by `radius`.
struct Capsule {
  Vec3d a{0.0}, b{1.0, 0.0, 0.0};
  double radius = 0.25;
  double operator()(const Vec3d& p) const {
    const Vec3d ab = b - a, ap = p - a;
    const double t = std::clamp(ap.dot(ab) / ab.dot(ab), 0.0, 1.0);
    return (ap - ab * t).length() - radius;
  }
};

/// Two spheres of radius `radius` whose centres are `separation` apart along x,
/// joined by a bar of radius `barRadius`: under curvature flow the bar pinches off.
struct Dumbbell {
  Vec3d centre{0.0};
  double radius = 1.0;
  double separation = 3.0;
  double barRadius = 0.35;
  double operator()(const Vec3d& p) const {
    const Vec3d offset(0.5 * separation, 0.0, 0.0);
    const double spheres = std::min(Sphere{centre - offset, radius}(p), Sphere{centre + offset, radius}(p));
    return std::min(spheres, Capsule{centre - offset, centre + offset, barRadius}(p));
  }
};

/// A cylinder around the z axis through `centre`, of radius `radius`, between
/// heights centre.z + zmin and centre.z + zmax, with flat caps.
struct CappedCylinder {
  Vec3d centre{0.0};
  double radius = 1.0;
  double zmin = -1.0, zmax = 1.0;
  double operator()(const Vec3d& p) const {
    const Vec3d q = p - centre;
    const double radial = std::sqrt(q.x() * q.x() + q.y() * q.y()) - radius;
    const double axial = std::fabs(q.z() - 0.5 * (zmin + zmax)) - 0.5 * (zmax - zmin);
    const double outside = std::sqrt(std::max(radial, 0.0) * std::max(radial, 0.0) +
                                     std::max(axial, 0.0) * std::max(axial, 0.0));
    return outside + std::min(std::max(radial, axial), 0.0);
  }
};

/// A mug standing on its base at `centre`, around the z axis (the paper's
/// Fig. 14): a cup of outer radius `radius` and height `height` whose wall and
/// bottom are `wall` thick, open at the top, and on its +x side a handle, a
/// tube of radius `handleRadius` bent in the xz plane around a circle of
/// radius `handleBend` centred on the wall at half height.
struct Mug {
  Vec3d centre{0.0};
  double radius = 1.0;
  double height = 2.0;
  double wall = 0.12;
  double handleBend = 0.55;
  double handleRadius = 0.12;
  double operator()(const Vec3d& p) const {
    const CappedCylinder outer{centre, radius, 0.0, height};
    const CappedCylinder hollow{centre, radius - wall, wall, height + 1.0};  // open at the top
    const double cup = std::max(outer(p), -hollow(p));
    const Vec3d h = p - centre - Vec3d(radius, 0.0, 0.5 * height);
    const double ring = std::sqrt(h.x() * h.x() + h.z() * h.z()) - handleBend;
    const double handle = std::max(std::sqrt(ring * ring + h.y() * h.y()) - handleRadius, -hollow(p));
    return std::min(cup, handle);
  }
};

/// A room seen from inside, `size` wide, deep and high, its floor on z = 0
/// around `centre` (on the floor), with things in it: a table, a ball on the
/// floor, a ring lying on the floor and a pillar from floor to ceiling. The
/// walls and the things are the solid (negative); the room's air is outside.
struct Room {
  Vec3d centre{0.0};
  Vec3d size{6.0, 4.0, 2.5};
  double operator()(const Vec3d& p) const {
    const Vec3d q = p - centre;
    const Box interior{Vec3d(0.0, 0.0, 0.5 * size.z()), 0.5 * size};
    const Box table{Vec3d(0.2 * size.x(), -0.2 * size.y(), 0.375), Vec3d(0.6, 0.4, 0.375)};
    const Sphere ball{Vec3d(-0.25 * size.x(), 0.25 * size.y(), 0.5), 0.5};
    const Torus ring{Vec3d(-0.15 * size.x(), -0.25 * size.y(), 0.15), 0.45, 0.15};
    const CappedCylinder pillar{Vec3d(0.3 * size.x(), 0.3 * size.y(), 0.0), 0.2, 0.0, size.z()};
    return std::min({-interior(q), table(q), ball(q), ring(q), pillar(q)});
  }
};

/// One of the analytic shapes the synthetic experiments use, chosen at run time.
struct AnalyticShape {
  enum class Kind { kSphere, kTorus, kMug, kRoom };
  Kind kind = Kind::kSphere;
  Sphere sphere;
  Torus torus;
  Mug mug;
  Room room;

  double operator()(const Vec3d& p) const {
    switch (kind) {
      case Kind::kSphere: return sphere(p);
      case Kind::kTorus: return torus(p);
      case Kind::kMug: return mug(p);
      case Kind::kRoom: return room(p);
    }
    return 0.0;
  }
  const char* name() const {
    switch (kind) {
      case Kind::kSphere: return "sphere";
      case Kind::kTorus: return "torus";
      case Kind::kMug: return "mug";
      case Kind::kRoom: return "room";
    }
    return "";
  }
};

}  // namespace levelfuse::shapes

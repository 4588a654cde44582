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

}  // namespace levelfuse::shapes

// levelfuse: the synthetic experiments' scenes.

#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <stdexcept>

namespace levelfuse::synth {

namespace {

using openvdb::Vec3d;
using Kind = shapes::AnalyticShape::Kind;

/// Views of a shape within `bounds` that needs `count` of them.
std::vector<View> viewsFor(const std::optional<shapes::AnalyticShape>& shape, const openvdb::BBoxd& bounds,
                           double margin, const SceneOptions& options) {
  const Vec3d centre = bounds.getCenter();
  const double extent = 1.2 * bounds.extents()[bounds.maxExtent()] + margin;
  const Kind kind = shape ? shape->kind : Kind::kSphere;
  const int count = options.views > 0 ? options.views : (shape && kind == Kind::kMug ? 10 : 6);
  std::vector<View> views;
  if (shape && kind == Kind::kTorus) {
    views = ringViews(centre, extent, options.resolution, count, 40.0);
  } else if (shape && kind == Kind::kMug && count >= 3) {
    views = ringViews(centre, extent, options.resolution, count - 2, 50.0);
    views.push_back(orthographicView(Vec3d(0, 0, -1), centre, extent, options.resolution, "top"));
    views.push_back(orthographicView(Vec3d(0, 0, 1), centre, extent, options.resolution, "bottom"));
  } else {
    views = viewsAround(centre, extent, options.resolution, count);
  }
  if (options.scanner == RangeMap::Kind::kPinhole)
    for (View& v : views) {
      const Vec3d forward = v.mapToWorld.transform3x3(Vec3d(0, 0, 1));
      v = pinholeView(centre - forward * 2.5 * extent, centre, 25.0, options.resolution, options.resolution, v.name);
    }
  if (options.scanner == RangeMap::Kind::kSpherical)
    for (View& v : views) {
      const Vec3d forward = v.mapToWorld.transform3x3(Vec3d(0, 0, 1));
      v = sphericalViewOf(centre - forward * 2.5 * extent, centre, 0.5 * std::sqrt(3.0) * extent, options.resolution,
                          v.name);
    }
  return views;
}

/// Renders every view with the options' noise. A spherical scanner's noise
/// grows with range: it is the options' at `noiseDistance` from the scanner.
template <typename Render>
void renderAll(Scene& scene, const std::vector<View>& views, const SceneOptions& options, double noiseDistance,
               const Render& render) {
  if (options.noise < 0.0 || options.outliers < 0.0 || options.outliers > 1.0)
    throw std::invalid_argument("synthetic scene: the noise must be >= 0 and the outliers a fraction in [0, 1]");
  Noise noise;
  noise.gaussianSigma = options.noise * scene.size;
  noise.replacementFraction = options.outliers;
  scene.noiseSigma = noise.gaussianSigma;
  if (options.scanner == RangeMap::Kind::kSpherical) {
    noise.gaussianPerReading = noise.gaussianSigma / noiseDistance;
    noise.gaussianSigma = 0.0;
  }
  const double sigma = std::max(scene.noiseSigma, 1e-3 * scene.size);  // the maps' stated noise, at least
  for (std::size_t i = 0; i < views.size(); ++i) {
    noise.seed = options.seed + i;
    scene.maps.push_back(render(views[i], noise, sigma));
  }
}

/// How far the scanners of viewsFor stand from the centre of `bounds`.
double scannerDistance(const openvdb::BBoxd& bounds, double margin) {
  return 2.5 * (1.2 * bounds.extents()[bounds.maxExtent()] + margin);
}

}  // namespace

shapes::AnalyticShape standardShape(Kind kind) {
  shapes::AnalyticShape shape;
  shape.kind = kind;
  shape.sphere = shapes::Sphere{Vec3d(0.0), 1.0};
  shape.torus = shapes::Torus{Vec3d(0.0), 1.0, 0.4};
  shape.mug = shapes::Mug{Vec3d(0.0, 0.0, -1.0)};
  return shape;
}

Scene analyticScene(const shapes::AnalyticShape& shape, const SceneOptions& options) {
  Scene scene;
  scene.truth = shape;
  openvdb::BBoxd bounds;
  switch (shape.kind) {
    case Kind::kSphere:
      bounds = openvdb::BBoxd(shape.sphere.centre - Vec3d(shape.sphere.radius), shape.sphere.centre + Vec3d(shape.sphere.radius));
      scene.size = 2.0 * shape.sphere.radius;
      scene.sizeName = "the diameter";
      break;
    case Kind::kTorus: {
      const double r = shape.torus.major + shape.torus.minor;
      bounds = openvdb::BBoxd(shape.torus.centre - Vec3d(r, r, shape.torus.minor),
                              shape.torus.centre + Vec3d(r, r, shape.torus.minor));
      scene.size = 2.0 * shape.torus.minor;
      scene.sizeName = "the tube's diameter";
      break;
    }
    case Kind::kMug: {
      const shapes::Mug& m = shape.mug;
      bounds = openvdb::BBoxd(m.centre - Vec3d(m.radius, m.radius, 0.0),
                              m.centre + Vec3d(m.radius + m.handleBend + m.handleRadius, m.radius, m.height));
      scene.size = 2.0 * m.handleRadius;
      scene.sizeName = "the handle's width";
      break;
    }
    case Kind::kRoom:  // seen from inside, by tripods: roomScene
      return roomScene(shape.room, options);
  }
  const auto distance = [&shape](const Vec3d& p) { return shape(p); };
  const double margin = 0.2 * scene.size;
  renderAll(scene, viewsFor(shape, bounds, margin, options), options, scannerDistance(bounds, margin),
            [&](const View& v, const Noise& n, double sigma) { return renderDistanceFunction(distance, v, n, sigma); });
  return scene;
}

Scene meshScene(const std::vector<Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles,
                const SceneOptions& options) {
  if (points.empty() || triangles.empty()) throw std::invalid_argument("synthetic scene: the mesh is empty");
  Scene scene;
  openvdb::BBoxd bounds;
  for (const Vec3d& p : points) bounds.expand(p);
  scene.size = bounds.extents()[bounds.maxExtent()];
  scene.sizeName = "the mesh's largest extent";
  const double margin = 0.2 * scene.size;
  renderAll(scene, viewsFor(std::nullopt, bounds, margin, options), options, scannerDistance(bounds, margin),
            [&](const View& v, const Noise& n, double sigma) { return renderMesh(points, triangles, v, n, sigma); });
  return scene;
}

Scene roomScene(const shapes::Room& room, const SceneOptions& options) {
  Scene scene;
  scene.truth = shapes::AnalyticShape{};
  scene.truth->kind = Kind::kRoom;
  scene.truth->room = room;
  scene.size = room.size.z();
  scene.sizeName = "the room's height";
  SceneOptions spherical = options;
  spherical.scanner = RangeMap::Kind::kSpherical;
  const double step = 90.0 / options.resolution;
  const Vec3d tripods[3] = {Vec3d(-0.3, -0.05, 0.6), Vec3d(0.1, 0.33, 0.6), Vec3d(0.05, -0.37, 0.6)};
  std::vector<View> views;
  for (int i = 0; i < 3; ++i) {
    const Vec3d at = room.centre + tripods[i] * room.size;
    views.push_back(sphericalView(at, -180.0, 180.0, -75.0, 75.0, step, "tripod " + std::to_string(i + 1)));
  }
  const auto distance = [&room](const Vec3d& p) { return room(p); };
  renderAll(scene, views, spherical, 1.0,
            [&](const View& v, const Noise& n, double sigma) { return renderDistanceFunction(distance, v, n, sigma); });
  return scene;
}

double streetSignedDistance(const Vec3d& x, double firstBay, double lastBay) {
  const double facade = 1.0 - x.y(), ground = x.z() + 1.2;
  // The nearest bay: every 2 m from the first.
  const double bayX = std::clamp(firstBay + 2.0 * std::round((x.x() - firstBay) / 2.0), firstBay, lastBay);
  const Vec3d q(std::fabs(x.x() - bayX) - 0.3, std::fabs(x.y() - 0.9) - 0.15, std::fabs(x.z() + 0.2) - 0.5);
  const Vec3d outside(std::max(q.x(), 0.0), std::max(q.y(), 0.0), std::max(q.z(), 0.0));
  const double bay = outside.length() + std::min(std::max(q.x(), std::max(q.y(), q.z())), 0.0);
  return std::min({facade, ground, bay});
}

Scene streetScene(const SceneOptions& options) {
  Scene scene;
  scene.size = 1.8;
  scene.sizeName = "the cameras' distance to the façade";
  SceneOptions cameras = options;
  cameras.scanner = RangeMap::Kind::kPinhole;
  const int count = options.views > 0 ? options.views : 40;
  const double length = 0.5 * (count - 1);
  const int width = options.resolution, height = std::max(2, options.resolution * 3 / 4);
  std::vector<View> views;
  for (int i = 0; i < count; ++i) {
    const double x = 0.5 * i - 0.5 * length;
    views.push_back(pinholeView(Vec3d(x, -0.8, -0.2), Vec3d(x, 1.0, -0.6), 60.0, width, height,
                                "street frame " + std::to_string(i)));
  }
  const double firstBay = -2.0 * std::floor(0.25 * length);
  const auto distance = [&](const Vec3d& p) { return streetSignedDistance(p, firstBay, -firstBay); };
  renderAll(scene, views, cameras, 1.0,
            [&](const View& v, const Noise& n, double sigma) { return renderDistanceFunction(distance, v, n, sigma); });
  return scene;
}

}  // namespace levelfuse::synth

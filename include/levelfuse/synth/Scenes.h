// levelfuse: the synthetic experiments' scenes: a shape, the views that see
// it, and its range maps with noise, as `levelfuse synth` makes them.
#pragma once

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/scan/RangeMap.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse::synth {

struct SceneOptions {
  int views = 0;          ///< 0: six (ten for the mug)
  int resolution = 200;   ///< pixels along each side of a view
  double noise = 0.0;     ///< Gaussian range noise as a fraction of the scene's size (see Scene::size)
  double outliers = 0.0;  ///< fraction of readings replaced by uniform outliers
  std::uint64_t seed = 1;
  /// The scanners: parallel rays, depth cameras, or spherical scanners whose
  /// noise grows with range (`noise` is then its standard deviation at the
  /// distance from the scanner to the shape's centre).
  RangeMap::Kind scanner = RangeMap::Kind::kOrthographic;
};

struct Scene {
  std::optional<shapes::AnalyticShape> truth;  ///< none for a mesh
  std::vector<RangeMap> maps;
  /// The size the noise is a fraction of, as in the paper: the sphere's
  /// diameter, the torus's tube diameter, the mug's handle width, a mesh's
  /// largest extent.
  double size = 1.0;
  std::string sizeName;
  double noiseSigma = 0.0;  ///< the Gaussian noise's standard deviation
};

/// The shapes of the experiments: a unit sphere; a torus of radii 1 and 0.4
/// around the z axis; the mug of shapes::Mug standing on z = -1.
shapes::AnalyticShape standardShape(shapes::AnalyticShape::Kind kind);

/// Range maps of an analytic shape: the torus from views around it alternately
/// above and below (so its inner wall is seen), the mug from views around it,
/// straight down into the cup and up at its base, the sphere from views spread
/// evenly; each view frames the shape with a margin.
Scene analyticScene(const shapes::AnalyticShape& shape, const SceneOptions& options = {});

/// The room of shapes::Room scanned from three tripods standing in it, each a
/// spherical scanner sweeping a whole turn and elevations from -75 to 75
/// degrees in steps of 90 / `resolution` degrees (the default 200: 0.45
/// degrees), its noise growing with range (`noise`, a fraction of the room's
/// height, is its standard deviation at 1 m). The views option is ignored.
Scene roomScene(const shapes::Room& room, const SceneOptions& options = {});

/// A street: a façade along x whose face is the plane y = 1 (solid beyond
/// it), with bays 60 cm wide standing 15 cm out of it every 2 m, on ground
/// solid below z = -1.2; negative inside solid, 1-Lipschitz. The façade and
/// the ground are unbounded; the bays stand from x = `firstBay` to `lastBay`.
double streetSignedDistance(const openvdb::Vec3d& x, double firstBay, double lastBay);

/// Depth frames along a street (streetSignedDistance), one every 50 cm from
/// eyes 1.8 m before the façade, each looking at it square on and a little
/// down (60 degrees across, `resolution` x 3/4 of it pixels): each frame sees
/// about 2 m of façade and ground, and the street grows with the frames
/// (`views`, 40 by default: 20 m). `noise` is a fraction of the cameras'
/// distance to the façade; no truth.
Scene streetScene(const SceneOptions& options = {});

/// Range maps of a triangle mesh from views spread evenly around it.
Scene meshScene(const std::vector<openvdb::Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles,
                const SceneOptions& options = {});

}  // namespace levelfuse::synth

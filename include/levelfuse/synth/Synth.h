// levelfuse: synthetic range maps of analytic shapes and triangle meshes.
//
// Test worlds for the reconstruction: render a shape from chosen viewpoints
// (orthographic, pinhole or spherical), add Gaussian range noise (a fraction of a stated
// size, as in the paper) and replacement noise (a fraction of readings replaced
// by uniform outliers), and keep the exact distance function to measure errors.
#pragma once

#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/Types.h>
#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec3.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse::synth {

/// A scanner: where it is, how it projects, and its image size.
struct View {
  RangeMap::Kind kind = RangeMap::Kind::kOrthographic;
  openvdb::math::Mat4d mapToWorld = openvdb::math::Mat4d::identity();  ///< rays along the map's +z
  int width = 200, height = 200;
  OrthographicProjection orthographic;
  PinholeProjection pinhole;
  SphericalProjection spherical;
  std::string name;
  /// How the view's pixels look into its frame: its kind's projection.
  MapProjection projection() const { return MapProjection::ofKind(kind, orthographic, pinhole, spherical); }
};

/// An orthographic view looking along `direction` (away from the scanner) at a
/// square of side `extent` centred on `centre`, `resolution` pixels a side.
View orthographicView(const openvdb::Vec3d& direction, const openvdb::Vec3d& centre, double extent, int resolution,
                      const std::string& name = "");
/// A spherical scanner at `eye` that sweeps only the directions toward the
/// ball of `radius` around `target` (a region scan), about `resolution`
/// rays across the ball.
View sphericalViewOf(const openvdb::Vec3d& eye, const openvdb::Vec3d& target, double radius, int resolution,
                     const std::string& name = "");
/// A pinhole camera at `eye` looking at `target`, with `fovDegrees` across its width.
View pinholeView(const openvdb::Vec3d& eye, const openvdb::Vec3d& target, double fovDegrees, int width, int height,
                 const std::string& name = "");
/// A spherical scanner standing at `position`, its z axis along the world's,
/// sweeping azimuths from `azimuthFrom` to `azimuthTo` and elevations from
/// `elevationFrom` to `elevationTo` (degrees; elevations strictly between the
/// poles) in steps of `stepDegrees`; a whole turn of azimuth repeats its first
/// column after its last.
View sphericalView(const openvdb::Vec3d& position, double azimuthFrom, double azimuthTo, double elevationFrom,
                   double elevationTo, double stepDegrees, const std::string& name = "");
/// Orthographic views from the six axis directions.
std::vector<View> sixAxisViews(const openvdb::Vec3d& centre, double extent, int resolution);
/// `count` orthographic views evenly spaced in azimuth about the z axis, looking
/// alternately down and up at `elevationDegrees` from the xy plane: views that
/// see all of a torus lying in that plane, its inner wall included.
std::vector<View> ringViews(const openvdb::Vec3d& centre, double extent, int resolution, int count,
                            double elevationDegrees);
/// `count` orthographic views spread evenly over a sphere (a golden-angle spiral).
std::vector<View> viewsAround(const openvdb::Vec3d& centre, double extent, int resolution, int count);

struct Noise {
  double gaussianSigma = 0.0;        ///< standard deviation of additive range noise (world units)
  /// More standard deviation per unit of a reading (a range or depth): noise
  /// that grows with distance, as a laser scanner's does. The maps then state
  /// their noise per reading (RangeMap::setDepthNoise).
  double gaussianPerReading = 0.0;
  double replacementFraction = 0.0;  ///< fraction of readings replaced by uniform outliers
  std::uint64_t seed = 1;
};

/// Renders a 1-Lipschitz signed distance function by sphere tracing: exact
/// first hits along every ray (`signedDistance` is called from several
/// threads at once). `sigma` is the range maps' stated noise. In the
/// maps of both renderers a pixel without a reading missed the shape: its
/// misses are empty (RangeMap::setMissesAreEmpty).
RangeMap renderDistanceFunction(const std::function<double(const openvdb::Vec3d&)>& signedDistance, const View& view,
                                const Noise& noise, double sigma);

/// Renders a triangle mesh by rasterising it into a depth buffer.
RangeMap renderMesh(const std::vector<openvdb::Vec3d>& points, const std::vector<openvdb::Vec3I>& triangles,
                    const View& view, const Noise& noise, double sigma);

/// The colour of a surface at a world point, for painting synthetic scans.
using SurfacePaint = std::function<Rgb8(const openvdb::Vec3d&)>;

/// Two colours on either side of the plane through `centre` across `axis`:
/// `above` where (x - centre) . axis >= 0, else `below`.
SurfacePaint twoColours(const openvdb::Vec3d& centre, const openvdb::Vec3d& axis, const Rgb8& above,
                        const Rgb8& below);

/// Gives every reading of `map` the paint's colour at the point it measured
/// (RangeMap::readingPoint), as a camera registered to the scanner would see
/// it; pixels without a reading are black.
void paintReadings(RangeMap& map, const SurfacePaint& paint);

}  // namespace levelfuse::synth

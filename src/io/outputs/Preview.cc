// levelfuse: shaded previews of level sets.

#include <levelfuse/core/Parallel.h>
#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/scan/SurfaceColour.h>

#include "../images/PngWrite.h"
#include <levelfuse/levelset/RequireLevelSet.h>

#include <openvdb/math/Ray.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/RayIntersector.h>


#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

namespace levelfuse::io {

namespace {

using openvdb::Vec3d;

/// Where a ray enters the surface, marched in steps of half a voxel and the
/// crossing interpolated linearly: a check of the ray intersector, which can
/// step over a surface met at a grazing angle near a node's edge.
class RayEntry {
 public:
  explicit RayEntry(const openvdb::FloatGrid& levelSet)
      : mAccess(levelSet.getConstAccessor()), mSampler(mAccess, levelSet.transform()),
        mVoxel(levelSet.voxelSize()[0]) {}
  bool outside(const Vec3d& x) const { return mSampler.wsSample(x) > 0.0; }
  /// The first point between `from` (outside) and `to` where the level set
  /// crosses zero, and the level set's gradient there; false if none is found.
  bool between(const Vec3d& from, const Vec3d& to, Vec3d& hit, Vec3d& normal) const {
    const double length = (to - from).length(), step = 0.5 * mVoxel;
    if (!(length > 0.0)) return false;
    const Vec3d direction = (to - from) / length;
    double before = mSampler.wsSample(from);
    for (double t = step; t <= length + step; t += step) {
      const Vec3d x = from + direction * std::min(t, length);
      const double value = mSampler.wsSample(x);
      if (value <= 0.0) {
        hit = x - direction * (step * value / (value - before));  // linear between the two samples
        for (int a = 0; a < 3; ++a) {
          Vec3d d(0.0);
          d[a] = mVoxel;
          normal[a] = mSampler.wsSample(hit + d) - mSampler.wsSample(hit - d);
        }
        return normal.length() > 0.0;
      }
      before = value;
    }
    return false;
  }

 private:
  openvdb::FloatGrid::ConstAccessor mAccess;
  openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> mSampler;
  double mVoxel;
};

/// A colour as scanners record it (sRGB-encoded, 0 to 1) in linear light, to shade.
Vec3d linearColour(const openvdb::Vec3f& encoded) {
  Vec3d linear;
  for (int c = 0; c < 3; ++c) linear[c] = std::pow(std::clamp(static_cast<double>(encoded[c]), 0.0, 1.0), 2.2);
  return linear;
}

std::uint8_t toByte(double linear) {
  const double srgb = std::pow(std::clamp(linear, 0.0, 1.0), 1.0 / 2.2);
  return static_cast<std::uint8_t>(std::lround(255.0 * srgb));
}

/// A camera's centre and axes (world): right and up span the picture, back
/// points away from what it looks at.
struct Camera {
  Vec3d eye, right, up, back;
};

/// Axes with `back` as given and `up` as near the wanted up as it can be.
Camera cameraAxes(const Vec3d& eye, const Vec3d& back, const Vec3d& wantedUp) {
  Camera camera{eye, wantedUp.cross(back), Vec3d(0.0), back};
  if (camera.right.length() < 1e-6) camera.right = Vec3d(0, 0, 1).cross(back);
  if (camera.right.length() < 1e-6) camera.right = Vec3d(0, 1, 0).cross(back);
  camera.right.normalize();
  camera.up = back.cross(camera.right);
  return camera;
}

Camera placedCamera(const PreviewCamera& placed) {
  if (!(placed.forward.length() > 0.0) || !std::isfinite(placed.forward.lengthSqr()) ||
      !std::isfinite(placed.eye.lengthSqr()))
    throw std::invalid_argument("preview: the camera needs a finite position and a direction to look in");
  return cameraAxes(placed.eye, -placed.forward.unit(), placed.up);
}

/// A camera outside the surface, looking at it from the options' direction and
/// framing its band: its leaf nodes' extents across and along the view.
Camera framingCamera(const openvdb::FloatGrid& levelSet, const PreviewOptions& options, double tanHalf,
                     double aspect) {
  Camera camera = cameraAxes(Vec3d(0.0), options.toward.length() > 0.0 ? options.toward.unit() : Vec3d(0, 0, 1),
                             options.up);
  Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  const double leafRadius = 0.5 * std::sqrt(3.0) * openvdb::FloatTree::LeafNodeType::DIM * levelSet.voxelSize()[0];
  for (auto leaf = levelSet.tree().cbeginLeaf(); leaf; ++leaf) {
    if (leaf->isEmpty()) continue;
    const Vec3d c = levelSet.indexToWorld(leaf->origin().asVec3d() + Vec3d(0.5 * (leaf->DIM - 1)));
    const Vec3d q(c.dot(camera.right), c.dot(camera.up), c.dot(camera.back));
    lo = openvdb::math::minComponent(lo, q - Vec3d(leafRadius));
    hi = openvdb::math::maxComponent(hi, q + Vec3d(leafRadius));
  }
  const Vec3d mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const double distance = 1.05 * std::max(half.x() / (tanHalf * aspect), half.y() / tanHalf) + half.z();
  camera.eye = camera.right * mid.x() + camera.up * mid.y() + camera.back * (mid.z() + distance);
  return camera;
}

/// A spherical scanner's view (seenByFrame).
PreviewOptions seenByScanner(const RangeMap& scan, PreviewOptions options) {
  const SphericalProjection& grid = scan.sphericalProjection();
  const double middle = grid.azimuthStart + 0.5 * (scan.width() - 1) * grid.azimuthStep;
  const openvdb::math::Mat4d& scannerToWorld = scan.mapToWorld();
  PreviewCamera camera;
  camera.eye = scannerToWorld.transform(Vec3d(0.0));
  camera.forward = scannerToWorld.transform3x3(Vec3d(std::cos(middle), std::sin(middle), 0.0));
  camera.up = scannerToWorld.transform3x3(Vec3d(0, 0, 1));
  options.camera = camera;
  options.fieldOfViewDegrees = 60.0;
  return options;
}

/// Surfaces a ray passes through where they are left out (PreviewOptions::weight), at most.
constexpr int kMaxSurfacesPassed = 64;

}  // namespace

PreviewOptions seenByFrame(const RangeMap& frame, PreviewOptions options) {
  if (frame.kind() == RangeMap::Kind::kSpherical) return seenByScanner(frame, options);
  if (frame.kind() != RangeMap::Kind::kPinhole)
    throw std::invalid_argument("preview: '" + frame.name() + "' has parallel rays: no camera stood anywhere");
  const PinholeProjection& k = frame.pinholeProjection();
  const openvdb::math::Mat4d& cameraToWorld = frame.mapToWorld();
  // The camera looks along its +z with image rows running down its +y.
  PreviewCamera camera;
  camera.eye = cameraToWorld.transform(Vec3d(0.0));
  camera.forward = cameraToWorld.transform3x3(Vec3d(0, 0, 1));
  camera.up = -cameraToWorld.transform3x3(Vec3d(0, 1, 0));
  options.camera = camera;
  const double tanHalfWidth = 0.5 * frame.width() / k.fx, tanHalfHeight = 0.5 * frame.height() / k.fy;
  options.fieldOfViewDegrees = 2.0 * std::atan(tanHalfHeight) * 180.0 / M_PI;
  options.height = std::max(8, static_cast<int>(std::lround(options.width * tanHalfHeight / tanHalfWidth)));
  return options;
}

void writePreviewPng(const openvdb::FloatGrid& levelSet, const std::string& path, const PreviewOptions& options) {
  OutputSet outputs;
  writePreviewPng(outputs, levelSet, path, options);
  outputs.commit();
}

namespace {

/// renderPreview's picture of a grid already found to be a level set.
PreviewImage rayCast(const openvdb::FloatGrid& levelSet, const PreviewOptions& options) {
  if (options.width < 8 || options.height < 8 || options.width > 16384 || options.height > 16384)
    throw std::invalid_argument("preview: the picture must be 8 to 16384 pixels a side");
  if (levelSet.activeVoxelCount() == 0) throw std::invalid_argument("preview: the level set '" + levelSet.getName() + "' has no surface");

  if (!(options.fieldOfViewDegrees > 0.0 && options.fieldOfViewDegrees < 180.0))
    throw std::invalid_argument("preview: the field of view must lie between 0 and 180 degrees");
  const double tanHalf = std::tan(0.5 * options.fieldOfViewDegrees * M_PI / 180.0);
  const double aspect = static_cast<double>(options.width) / options.height;
  const Camera camera =
      options.camera ? placedCamera(*options.camera) : framingCamera(levelSet, options, tanHalf, aspect);
  const Vec3d &eye = camera.eye, &right = camera.right, &up = camera.up, &back = camera.back;

  // A key light from the upper left and a fill from the camera.
  const Vec3d key = (up * 0.8 - right * 0.5 + back * 0.6).unit();
  const Vec3d albedo(0.86, 0.80, 0.70);
  PreviewImage image{options.width, options.height, {}};
  std::vector<std::uint8_t>& rgb = image.rgb;
  rgb.resize(static_cast<std::size_t>(options.width) * options.height * 3);
  const openvdb::tools::LevelSetRayIntersector<openvdb::FloatGrid> shared(levelSet);
  const double passStep = 0.5 * levelSet.voxelSize()[0];  // past a surface left out
  parallelFor(static_cast<std::size_t>(options.height), 4, [&](std::size_t begin, std::size_t end) {
    openvdb::tools::LevelSetRayIntersector<openvdb::FloatGrid> intersector(shared);  // one accessor per task
    std::optional<openvdb::FloatGrid::ConstAccessor> weight;
    if (options.weight) weight.emplace(options.weight->getConstAccessor());
    const RayEntry entry(levelSet);
    std::optional<ColourSampler> paint;  // the surface's colour, if given
    if (options.colour) paint.emplace(*options.colour);
    // The first surface along the ray that is drawn.
    const auto drawnHit = [&](const Vec3d& direction, Vec3d& hit, Vec3d& normal) {
      double start = 0.0, time = 0.0;
      for (int pass = 0; pass < kMaxSurfacesPassed; ++pass) {
        if (!intersector.intersectsWS(openvdb::math::Ray<double>(eye, direction, start), hit, normal, time))
          return false;
        // A ray from outside meets a front face first: if the intersector
        // stopped at a back face, it stepped over the front one.
        const Vec3d from = eye + direction * start, backFace = hit;
        if (normal.dot(direction) > 0.0 && entry.outside(from) && entry.between(from, backFace, hit, normal))
          time = (hit - eye).length();
        if (!weight) return normal.length() > 0.0;
        const double observed = openvdb::tools::BoxSampler::sample(*weight, options.weight->worldToIndex(hit));
        if (observed >= options.minWeight) return normal.length() > 0.0;
        start = time + passStep;
      }
      return false;
    };
    for (std::size_t y = begin; y < end; ++y)
      for (int x = 0; x < options.width; ++x) {
        const double sx = (2.0 * (x + 0.5) / options.width - 1.0) * tanHalf * aspect;
        const double sy = (1.0 - 2.0 * (y + 0.5) / options.height) * tanHalf;
        const Vec3d direction = (right * sx + up * sy - back).unit();
        Vec3d hit, normal;
        Vec3d colour;
        if (drawnHit(direction, hit, normal)) {
          normal.normalize();
          if (normal.dot(direction) > 0.0) normal = -normal;  // seen from inside: shade the back face alike
          const double diffuse = 0.75 * std::max(0.0, normal.dot(key)) + 0.35 * std::max(0.0, -normal.dot(direction));
          const Vec3d halfway = (key - direction).unit();
          const double specular = 0.15 * std::pow(std::max(0.0, normal.dot(halfway)), 40.0);
          const Vec3d surfaceAlbedo = paint ? linearColour(paint->at(hit)) : albedo;
          colour = surfaceAlbedo * (0.08 + diffuse) + Vec3d(specular);
        } else {
          const double t = static_cast<double>(y) / options.height;
          colour = Vec3d(0.30, 0.33, 0.38) * (1.0 - t) + Vec3d(0.12, 0.13, 0.15) * t;
        }
        std::uint8_t* pixel = &rgb[(y * options.width + x) * 3];
        for (int c = 0; c < 3; ++c) pixel[c] = toByte(colour[c]);
      }
  });
  return image;
}

}  // namespace

PreviewImage renderPreview(const openvdb::FloatGrid& levelSet, const PreviewOptions& options) {
  requireLevelSet(levelSet, "renderPreview");
  return rayCast(levelSet, options);
}

void writePreviewPng(OutputSet& outputs, const openvdb::FloatGrid& levelSet, const std::string& path,
                     const PreviewOptions& options) {
  requireLevelSet(levelSet, "writePreviewPng");
  const PreviewImage image = rayCast(levelSet, options);
  outputs.add(path, [&](const std::string& temporary) { detail::writeRgbPng(temporary, image.width, image.height, image.rgb); });
}

}  // namespace levelfuse::io

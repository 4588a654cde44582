// levelfuse: one range map (a scan): a 2D grid of range readings along lines
// of sight, its scanner geometry and its pose (section 3 of the paper).
//
// Its pixels look into its frame through its projection (MapProjection.h:
// parallel rays, a pinhole camera or a spherical grid).
// Optional per-pixel ray directions refine the lines of sight of scanners
// whose rays are neither parallel nor through one centre; pixels are still
// found through the map's projection.
#pragma once

#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/MapProjection.h>
#include <levelfuse/scan/PixelFlags.h>

#include <openvdb/Types.h>
#include <openvdb/math/BBox.h>
#include <openvdb/math/Mat4.h>
#include <openvdb/math/Vec2.h>
#include <openvdb/math/Vec3.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse {

/// What a range map says about a world point x (Eqs. 13, 17, 38).
struct RangeSample {
  double D = 0.0;                ///< signed distance along the line of sight from the reading to x; > 0 behind it
  openvdb::Vec3d gradD{0.0};     ///< gradient of D (world)
  openvdb::Vec3d lineOfSight{0.0};  ///< unit direction of the line of sight, away from the scanner (world)
  double gamma = 0.0;            ///< rays per unit area at x (the Jacobian of Eq. 13)
  double sigma = 0.0;            ///< standard deviation of the reading (world units)
};

/// The widest field of view (degrees, across the image) RangeMap::pinhole
/// takes: a rectilinear camera's image stretches without bound toward 180.
inline constexpr double kWidestPinholeView = 170.0;

/// Per-reading noise that follows the reading: sigma(z) = max(minimum,
/// perMetre z + perSquareMetre z^2), z the depth (a camera's) or the range (a
/// spherical scanner's), in metres. Structured-light cameras lose precision
/// with the square of the depth; laser scanners' specifications state a
/// constant and a part per metre of range.
struct DepthNoise {
  double minimum = 0.001;
  double perSquareMetre = 0.0015;
  double perMetre = 0.0;
  /// sigma at depth or range z (metres).
  double at(double z) const { return std::max(minimum, perSquareMetre * z * z + perMetre * z); }
};

class RangeMap {
 public:
  using Kind = MapProjection::Kind;

  /// `readings` is row-major, `width * height` values in world units; NaN or
  /// values <= 0 (pinhole) mean no reading. `mapToWorld` is rigid. A pinhole
  /// map's readings are depths along the optical axis, and `cameraToWorld`
  /// takes the camera frame (x right, y down, z along the optical axis:
  /// OpenCV's) to world, in OpenVDB's row-vector layout (p_world = p_camera *
  /// M). Open3D's extrinsic (in integrate()) is world-to-camera: pass its
  /// inverse. Throws
  /// std::invalid_argument for inconsistent sizes or geometry (a pinhole whose
  /// field of view reaches kWidestPinholeView).
  static RangeMap orthographic(int width, int height, std::vector<float> readings, const OrthographicProjection& p,
                               const openvdb::math::Mat4d& mapToWorld, double sigma, std::string name = "");
  static RangeMap pinhole(int width, int height, std::vector<float> depths, const PinholeProjection& p,
                          const openvdb::math::Mat4d& cameraToWorld, double sigma, std::string name = "");
  /// A depth camera's frame: pinhole() with sigmas that follow the depth, as
  /// setDepthNoise gives them, without working the map out twice.
  static RangeMap pinhole(int width, int height, std::vector<float> depths, const PinholeProjection& p,
                          const openvdb::math::Mat4d& cameraToWorld, const DepthNoise& noise, std::string name = "");

  /// A scan on a spherical grid: `ranges` row-major (a row per elevation, a
  /// column per azimuth), distances from the scanner in world units, NaN or
  /// values <= 0 for no return. `scannerToWorld` is rigid, in OpenVDB's
  /// row-vector layout. Throws std::invalid_argument for inconsistent sizes or
  /// geometry (a step of zero, a row at or beyond a pole, more than a turn,
  /// row elevations that are not one per row or not increasing). With
  /// `p.rowElevations`, the map's elevation start and step are taken from them.
  static RangeMap spherical(int width, int height, std::vector<float> ranges, const SphericalProjection& p,
                            const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name = "");
  /// The same with sigmas that follow the range (setDepthNoise); the map's
  /// sigma is the noise's at 1 m.
  static RangeMap spherical(int width, int height, std::vector<float> ranges, const SphericalProjection& p,
                            const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise,
                            std::string name = "");

  /// Per-pixel lines of sight (unit vectors in the map frame, away from the
  /// scanner), e.g. for scanners with a fan of rays per row.
  void setRayDirections(std::vector<openvdb::Vec3f> directions);
  bool hasRayDirections() const { return !mDirections.empty(); }
  /// Per-pixel standard deviations (world units), replacing the map's sigma.
  void setSigmas(std::vector<float> sigmas);
  /// Standard deviations that follow the readings' depth (world units, the
  /// depth along the optical axis), replacing the map's sigma and any
  /// per-pixel ones: what setSigmas would hold, computed where it is needed
  /// instead of held per pixel, where they would weigh as much as the readings
  /// (docs/BENCHMARKS.md, "Depth video").
  void setDepthNoise(const DepthNoise& noise);
  /// The noise that the sigmas follow (setDepthNoise), or none.
  const DepthNoise* depthNoise() const { return mHasDepthNoise ? &mDepthNoise : nullptr; }
  /// Per-pixel colours (row after row, as the readings), recorded with the
  /// readings: a terrestrial scanner's camera, a depth frame's registered
  /// colour image; none takes them away. Throws std::invalid_argument unless
  /// there is one per pixel.
  void setColours(std::vector<Rgb8> colours);
  bool hasColours() const { return !mColours.empty(); }
  const std::vector<Rgb8>& colours() const { return mColours; }
  /// The colour seen along the line of sight through `p` (in the map's frame),
  /// from 0 to 1, interpolated bilinearly between the four pixels around it as
  /// the reading is; false where the map has no colours or `p` falls where no
  /// reading is interpolated (sampleLocal).
  bool colourAt(const openvdb::Vec3d& p, openvdb::Vec3f& rgb) const;
  /// The points the scanner measured (world units), `raySpacing` apart, where
  /// an orthographic map was resampled from them on finer pixels (a range grid
  /// rasterised along the line of sight). The fit of a surface to the data is
  /// measured at these, not at the interpolated readings of the pixels, and
  /// the ray density gamma (Eq. 13) is the scanner's, 1 / raySpacing^2, not
  /// the pixels'. Throws for a pinhole map, a point that is not finite, or a
  /// spacing that is not positive.
  void setSamples(std::vector<openvdb::Vec3d> worldPoints, double raySpacing);
  /// The measured points if set (setSamples), else none: the readings are the samples.
  const std::vector<openvdb::Vec3d>& samples() const { return mSamples; }
  /// Points the scanner measured: the samples if set, else the valid readings.
  std::size_t sampleCount() const {
    if (mSamplesLetGo > 0) return mSamplesLetGo;
    return mSamples.empty() ? mValidCount : mSamples.size();
  }
  /// Lets go of the measured points (setSamples), which only the fit of a
  /// surface to the data reads (recon/DataFit.h), in a process that will not
  /// measure it: sampleCount() still counts them, and measureDataFit refuses
  /// the map. Nothing changes for a map whose readings are the samples.
  void letSamplesGo();
  /// Whether letSamplesGo() let measured points go.
  bool samplesLetGo() const { return mSamplesLetGo > 0; }
  /// A 2x2 cell whose readings differ by more than `factor` times the distance
  /// between its rays, plus six sigma of noise (four standard deviations of
  /// the difference of two readings), is a depth discontinuity: never
  /// interpolated across. The factor is 4 by default. A surface seen at
  /// grazing incidence theta spreads a cell's readings over about tan(theta)
  /// ray spacings (4 at 76 degrees), smoothly: a cell that spans more than
  /// `factor` spacings is still interpolated when it spans at most
  /// kSteepSlopeSpacings of them (plus the noise; about 85 degrees) and, along
  /// each of the map's axes, its readings change by at most
  /// kSteepSlopeStepRatio times the smaller change of the cells beside it on
  /// that axis, plus the noise. A depth step stands out from its neighbours,
  /// from the one on the far surface at least where the near one is steep (a
  /// pillar's side at grazing incidence before a wall).
  void setDiscontinuityFactor(double factor);
  /// The most ray spacings a cell on a steep smooth surface may span (see
  /// setDiscontinuityFactor), on top of six sigma of noise.
  static constexpr double kSteepSlopeSpacings = 12.0;
  /// How many times the change of its neighbours along an axis the readings
  /// of a cell on a steep smooth surface may change along it (see
  /// setDiscontinuityFactor), on top of six sigma of noise.
  static constexpr double kSteepSlopeStepRatio = 3.0;

  /// The reading on the line of sight through x, interpolated bilinearly
  /// between the four surrounding readings; false where one of them is missing
  /// or they straddle a depth discontinuity (then x gets no data from this map).
  bool sample(const openvdb::Vec3d& x, RangeSample& out) const;

  /// The fast path of accumulation: D, grad D, the line of sight, gamma and
  /// sigma at a point given in the map's frame (vectors in the map's frame),
  /// or false if there is no reading or |D| > reach.
  struct LocalSample {
    double D, gradDSquared, gamma, sigma;
    openvdb::Vec3d gradD, lineOfSight;
  };
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool sampleLocal(const openvdb::Vec3d& p, double reach, LocalSample& out) const;
  /// sampleLocal along this map's own rays, of the kind that its projection
  /// visits (projection().visit): a loop over many points of one map visits
  /// once and calls these inside, the kind told apart once per map.
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool sampleLocal(const ParallelRays& rays, const openvdb::Vec3d& p, double reach, LocalSample& out) const;
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool sampleLocal(const PinholeRays& rays, const openvdb::Vec3d& p, double reach, LocalSample& out) const;
  /// sampleLocal of a point in front of the camera (rays.canProject(p)) at
  /// the pixel coordinates `uv` that rays.pixelOf(p) gave: for a loop that
  /// culls its points by their pixels before it samples them.
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool sampleLocalAtPixel(const PinholeRays& rays, const openvdb::Vec3d& p, const openvdb::math::Vec2d& uv,
                          double reach, LocalSample& out) const;
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool sampleLocal(const SphericalRays& rays, const openvdb::Vec3d& p, double reach, LocalSample& out) const;
  /// What the line of sight through a point says about it, away from the
  /// reading (space carving, as in VRIP's hole filling).
  enum class Sight {
    kOutside,  ///< no line of sight of the map passes the point
    kUnknown,  ///< near the reading, or a pixel without one (a dropout)
    kEmpty,    ///< the ray passed the point before its reading, or missed everything
    kBehind,   ///< the point lies behind the reading
  };
  /// The sight of world point x from the four pixels around it. Where their
  /// cell is usable (cellUsable), the reading interpolated there as the data
  /// term interpolates it decides: empty if x lies in front of it by more
  /// than `margin`, behind if behind it by more than `margin` (depths along
  /// the optical axis for a pinhole), else unknown: with the data window's
  /// reach for margin, every point of the line of sight that the data term
  /// does not reach is either empty or behind. Elsewhere the four
  /// must agree: empty if x lies in front of all their readings by more than
  /// `margin` (or a pixel missed, where misses are empty, see below), behind
  /// if it lies behind all four by more than `margin`, unknown where they
  /// disagree.
  Sight sight(const openvdb::Vec3d& x, double margin) const;
  /// False only where sight() says kOutside at every point of the world box
  /// `box`, whatever the readings: the box lies behind the camera, or beside
  /// its pixels. A map for which it is false says nothing of the box (space
  /// carving there needs no reading of it). True for spherical maps, and
  /// for a box that reaches behind a camera and in front of it. Asks the map's
  /// projection and pose alone (a PackedRangeMap's shell answers).
  bool mayBeSeenIn(const openvdb::BBoxd& box) const;
  /// True only where sight() says kOutside at every point within `radius` of
  /// world point `centre`, whatever the readings: the ball lies beside
  /// parallel rays' lattice, or behind a camera or beyond a side of its
  /// frustum. Never for spherical maps. A handful of products (mayBeSeenIn
  /// projects a box's eight corners), for the many blocks a map does not see.
  bool missesBall(const openvdb::Vec3d& centre, double radius) const;
  /// sight(x[i], margin) into out[i] for `count` points: the same answers,
  /// with the points' projections worked out together before their readings
  /// are read (carving asks a block's voxels so).
  void sights(const openvdb::Vec3d* x, std::size_t count, double margin, Sight* out) const;
  /// Pixels without a reading saw empty space along their whole line of sight
  /// (the ray missed the object), as for synthetic renderings and turntable
  /// scans against an empty background. Off by default: depth cameras also
  /// lose readings on dark or shiny surfaces. Even when on, a pixel within
  /// `dropoutReach` pixels of a reading is taken for a dropout, not a miss
  /// (0 for exact renderings, whose every miss is real).
  void setMissesAreEmpty(bool empty, int dropoutReach = 2);
  bool missesAreEmpty() const { return !mMisses.empty(); }
  int dropoutReach() const { return mDropoutReach; }

  /// The readings are whole multiples of this step (world units), as a 16-bit
  /// depth image's are of its depth scale; 0 (the default) if they are not
  /// known to be. A hint, checked where it is used: PackedRangeMap holds
  /// readings that are exactly 1 to 65535 steps as 16-bit integers. Throws
  /// std::invalid_argument for a step that is negative or not finite.
  void setReadingStep(double step);
  double readingStep() const { return mReadingStep; }

  /// Transforms world points into the map's frame.
  const openvdb::math::Mat4d& worldToMap() const { return mWorldToMap; }
  /// Smallest and largest reading over the pixels of the window [u0, u1] x
  /// [v0, v1] (clamped to the map), from per-block bounds; false if none is valid.
  /// `complete`, if given, is told whether every pixel of the window has a
  /// reading (false when unsure: the blocks around the window are asked).
  bool readingBounds(double u0, double v0, double u1, double v1, double& lo, double& hi,
                     bool* complete = nullptr) const;
  /// Whether `test(reading)` holds at every pixel from i0 to i1 and from j0 to
  /// j1 (clamped to the map; the reading is NaN where a pixel has none): the
  /// pixels are read in order until one fails.
  template <typename Test>
  bool everyPixel(int i0, int j0, int i1, int j1, const Test& test) const {
    i0 = std::max(i0, 0);
    i1 = std::min(i1, mWidth - 1);
    for (int j = std::max(j0, 0); j <= std::min(j1, mHeight - 1); ++j) {
      const float* row = mReadings.data() + index(0, j);
      for (int i = i0; i <= i1; ++i)
        if (!test(row[i])) return false;
    }
    return true;
  }
  /// Whether cell (i, j), between pixels i to i + 1 and j to j + 1, is usable:
  /// its four readings are valid and span no depth discontinuity
  /// (setDiscontinuityFactor says which do).
  bool cellUsable(int i, int j) const { return mUsableCell[index(i, j)]; }
  /// The readings a station's surface extended beyond its last rays may give
  /// in cell (i, j), which is not usable (sample's edge extension): false if
  /// it gives none there (a usable cell, a map that is no station, no corner
  /// to extend), else between lo and hi.
  bool edgeReadings(int i, int j, float& lo, float& hi) const;
  /// How far an edge's extension may take a reading from the pixel's own
  /// (world units): 0 but for a station.
  double edgeExtensionReach(double reading) const;
  /// How far beyond its outermost pixels' centres a map's surface extends, in
  /// pixels: a station's by half a pixel (each pixel's ray stands for the
  /// half pixel on either side of it, the outermost ones too), along the
  /// slopes of the cells at its border; 0 for other maps.
  double borderReach() const { return isStation() ? kBorderReach : 0.0; }
  /// The readings usable cell (i, j) interpolates, or extrapolates over the
  /// border beside it (borderReach): false if the cell is not usable.
  bool usableCellSpan(int i, int j, float& lo, float& hi) const;
  /// Pixel coordinates of a point in the map's frame (may lie outside the
  /// map): MapProjection::pixelOf.
  openvdb::math::Vec2d project(const openvdb::Vec3d& p) const { return mProjection.pixelOf(p); }
  /// Whether project() answers for a point in the map's frame: MapProjection::canProject.
  bool canProject(const openvdb::Vec3d& p) const { return mProjection.canProject(p); }

  /// How the map's pixels look into its frame.
  const MapProjection& projection() const { return mProjection; }
  Kind kind() const { return mProjection.kind(); }
  int width() const { return mWidth; }
  int height() const { return mHeight; }
  const std::string& name() const { return mName; }
  double sigma() const { return mSigma; }
  const openvdb::math::Mat4d& mapToWorld() const { return mMapToWorld; }
  const OrthographicProjection& orthographicProjection() const { return mProjection.orthographic(); }
  const PinholeProjection& pinholeProjection() const { return mProjection.pinhole(); }
  const SphericalProjection& sphericalProjection() const { return mProjection.spherical(); }
  /// True when the lines of sight fan out from the scanner's position (a
  /// camera, a spherical scanner): such a map sees the surfaces around it, and
  /// says nothing of points outside its view.
  bool raysFromOneCentre() const { return mProjection.raysFromOneCentre(); }
  /// True for a scan of a scene around its scanner rather than of an object
  /// before it: a depth frame (a camera among the surfaces it films), or a
  /// spherical scan (a station of a terrestrial scanner or a LiDAR sweep,
  /// which measures whatever surrounds it, a room, a street, a plant, and
  /// sees each surface from one side).
  bool ofAScene() const;
  /// The quantity a point's readings are compared with, for a point in the
  /// map's frame: its z along parallel rays or a camera's optical axis, its
  /// distance from a spherical scanner.
  double readingCoordinate(const openvdb::Vec3d& p) const { return mProjection.readingOf(p); }
  /// Columns in a full turn of a spherical map (2 pi / |azimuth step|).
  double azimuthPeriod() const { return mProjection.azimuthPeriod(); }

  bool valid(int u, int v) const { return mReadings[index(u, v)] == mReadings[index(u, v)]; }
  float reading(int u, int v) const { return mReadings[index(u, v)]; }
  std::size_t validCount() const { return mValidCount; }
  /// World position of the surface point a reading measured.
  openvdb::Vec3d readingPoint(int u, int v) const;
  /// World box of the points the readings measured (empty without readings).
  const openvdb::BBoxd& readingBounds() const { return mReadingBounds; }
  /// World position of the point at pixel coordinates (u, v) (not necessarily
  /// a pixel centre) with the given reading: depth z along the parallel rays or
  /// the optical axis.
  openvdb::Vec3d pointAt(double u, double v, double reading) const;
  /// World position of the scanner for a pinhole camera; for parallel rays a
  /// point far behind the readings along the line of sight.
  openvdb::Vec3d scannerPosition() const;
  /// Largest distance between neighbouring rays at the readings (world units):
  /// the scanner's, for a map resampled from its samples.
  double maxRaySpacing() const;
  /// The distance between neighbouring rays where most of the surface is seen
  /// (world units): for a spherical scanner, whose rays spread over ranges of
  /// many times the nearest, the side of the patch a ray has to itself at the
  /// median reading (median range x sqrt(azimuth step x elevation step)); for
  /// other maps maxRaySpacing().
  double typicalRaySpacing() const;

  /// Memory held (bytes): the readings and what the map derived from them.
  std::size_t memoryBytes() const;

 private:
  friend class PackedRangeMap;  // compresses and restores the per-pixel arrays
  RangeMap(MapProjection projection, int width, int height, std::string name)
      : mProjection(std::move(projection)), mWidth(width), mHeight(height), mName(std::move(name)) {}
  /// A spherical scan, a station's: its surface ends half a pixel beyond its
  /// border rays (borderReach, extendEdge), and its rays spread over ranges
  /// of many times the nearest (typicalRaySpacing).
  bool isStation() const { return mProjection.kind() == Kind::kSpherical; }
  std::size_t index(int u, int v) const {
    return static_cast<std::size_t>(v) * static_cast<std::size_t>(mWidth) + static_cast<std::size_t>(u);
  }
  /// sight() of a point in the map's frame at pixel coordinates (u, v) and
  /// reading coordinate `along`, from the four pixels around it.
  Sight sightAtPixel(double u, double v, double along, double margin) const;
  /// `m` given its readings, pose and sigma (finish).
  static RangeMap finished(RangeMap m, std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld,
                           double sigma);
  /// `m` given its readings and pose, its sigmas following `noise` (the map's
  /// sigma is the noise's at 1 m).
  static RangeMap finished(RangeMap m, std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld,
                           const DepthNoise& noise);
  /// A spherical map of checked geometry that has yet to be given its readings (finish).
  static RangeMap sphericalWithoutReadings(int width, int height, SphericalProjection p, std::string name);
  /// A pinhole map of checked geometry that has yet to be given its readings (finish).
  static RangeMap pinholeWithoutReadings(int width, int height, const PinholeProjection& p, std::string name);
  void finish(std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld, double sigma);
  /// The world box of the reading points, worked out once (finish).
  openvdb::BBoxd boundsOfReadings() const;
  /// Calls visit(x) with the world point x of each reading, row by row, along
  /// the map's own `rays` (its projection's visit).
  template <typename Rays, typename Visit>
  void forEachReadingPoint(const Rays& rays, const Visit& visit) const;
  /// The same along a camera's rays, with the same arithmetic, the slopes of
  /// each column and row worked out once.
  template <typename Visit>
  void forEachReadingPoint(const PinholeRays& rays, const Visit& visit) const;
  /// Takes sigmas that follow the depth, replacing any others, without
  /// working the usable cells out again; throws unless `noise` is positive
  /// and finite.
  void adoptDepthNoise(const DepthNoise& noise);
  /// The line of sight and sigma of the pixel nearest (i + fu, j + fv), into
  /// a sample found in cell (i, j): the end of each sampleLocal; true.
  bool nearestPixelSays(int i, int j, double fu, double fv, LocalSample& out) const;
  /// The standard deviation of pixel `at`'s reading: per pixel, from its depth, or the map's.
  double sigmaAt(std::size_t at) const {
    if (!mSigmas.empty()) return mSigmas[at];
    return mHasDepthNoise ? depthNoiseSigma(mReadings[at]) : mSigma;
  }
  /// sigma(z) of the depth noise, as a float; a pixel without a reading counts as 1 m deep.
  float depthNoiseSigma(float reading) const {
    const double z = reading == reading ? reading : 1.0;
    // Readings so far away that their sigma overflows a float carry no weight anyway.
    const double sigma = mDepthNoise.at(z);
    return static_cast<float>(std::min(sigma, double(std::numeric_limits<float>::max())));
  }
  /// The median of the readings (0 without readings).
  double medianReading() const;
  /// Marks the 2x2 cells of readings that may be interpolated.
  void findUsableCells();
  /// The readings of cell (i, j), at pixels (i, j), (i + 1, j), (i, j + 1) and
  /// (i + 1, j + 1); false unless the cell lies in the map and all four are
  /// valid. Inlined into findUsableCells, which asks it of every cell.
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  inline bool cellReadings(int i, int j, double (&r)[4]) const;
  /// Whether cell (i, j), whose readings `r` are valid and may differ by
  /// `noise` on top of the surface's own change, spans no depth
  /// discontinuity (the rule setDiscontinuityFactor states); `rays` are the
  /// map's own (its projection's visit).
  template <typename Rays>
  bool spansNoDiscontinuity(const Rays& rays, int i, int j, const double (&r)[4], double noise) const;
  /// Whether the readings of cell (i, j) change along each axis by at most
  /// kSteepSlopeStepRatio times the smaller change of its neighbours on that
  /// axis (those with readings; none: false), plus `noise`: the cell lies on
  /// a smooth surface, however steep.
  bool changesLikeItsNeighbours(int i, int j, const double (&r)[4], double noise) const;
  /// The reading interpolated bilinearly at fraction (fu, fv) of the cell
  /// whose first pixel is `at` (Eq. 13's r_j(x)).
  double bilinearReading(std::size_t at, double fu, double fv) const;
  /// Works out mBlockMin, mBlockMax and mBlockComplete from the readings.
  void findBlockBounds();
  /// Whether a camera's point of depth z at pixel (u, v) lies farther than
  /// `reach` in depth from every reading of the block of pixels its cell lies
  /// in: a test cheaper than the interpolation that finds the same (false
  /// where it cannot tell: the cell ends its block, or lies outside the map).
  bool outsideBlockWindow(double u, double v, double z, double reach) const;
  /// Shared by sample() and sampleLocal(): the bilinear reading at pixel (u, v)
  /// and its derivatives; false without one. Inlined into the samplers, whose
  /// loops over many points it is the heart of.
#if defined(__GNUC__)
  __attribute__((always_inline))
#endif
  bool interpolate(double u, double v, double& r, double& ru, double& rv, int& i, int& j, double& fu,
                   double& fv) const;
  /// The steepest an edge's surface is extended beyond its last ray
  /// (extendEdge): two ray spacings of range a pixel (63 degrees of
  /// incidence), so that half a pixel moves a reading by at most one spacing.
  static constexpr double kSteepestEdgeSlope = 2.0;
  /// A station's border: half a pixel (borderReach).
  static constexpr double kBorderReach = 0.5;
  /// A station's surface reaches half a pixel beyond its last rays: in cell
  /// (i, j), which may not be interpolated (it straddles a depth step or a
  /// missing reading), the reading of the pixel nearest (i + fu, j + fv),
  /// extended along the slopes of the usable cells it is a corner of (no
  /// steeper than kSteepestEdgeSlope); false
  /// if that pixel has no reading or is a corner of no usable cell (a lone
  /// return, such as a mixed pixel). fu and fv become that pixel's corner of
  /// the cell (0 or 1), so that what is blended across the cell (colours)
  /// is that pixel's.
  bool extendEdge(int i, int j, double& fu, double& fv, double& r, double& ru, double& rv) const;
  /// Whether pixel (u, v) has a reading and is a corner of a usable cell:
  /// one an edge's surface may be extended from.
  bool extendableCorner(int u, int v) const;
  /// Calls visit(i, j) for each usable cell (i, j) that pixel (u, v) is a corner of.
  template <typename Visit>
  void forEachUsableCellAt(int u, int v, const Visit& visit) const;

  static constexpr int kBlock = 8;  ///< pixels per side of a block of reading bounds
  int mBlocksX = 0, mBlocksY = 0;
  std::vector<float> mBlockMin, mBlockMax;  ///< per block, NaN if it has no reading
  std::vector<std::uint8_t> mBlockComplete;  ///< per block, 1 if every pixel of it has a reading

  MapProjection mProjection;
  int mWidth = 0, mHeight = 0;
  std::string mName;
  std::vector<float> mReadings;  ///< NaN where there is no reading
  /// Per cell (i, j) between pixels i..i+1, j..j+1: true if its four readings
  /// are valid and span no depth discontinuity (spansNoDiscontinuity; indexed
  /// like the pixels; a bit per cell).
  PixelFlags mUsableCell;
  std::vector<openvdb::Vec3f> mDirections;
  std::vector<float> mSigmas;
  std::vector<Rgb8> mColours;  ///< per pixel, or none
  bool mHasDepthNoise = false;  ///< the sigmas follow mDepthNoise
  DepthNoise mDepthNoise;
  std::vector<openvdb::Vec3d> mSamples;  ///< world; empty where the readings are the samples
  std::size_t mSamplesLetGo = 0;  ///< how many samples letSamplesGo() let go
  PixelFlags mMisses;  ///< per pixel: no reading within the dropout reach (if misses are empty)
  int mDropoutReach = 2;
  std::size_t mValidCount = 0;
  double mLargestReading = 0.0;  ///< the largest reading (0 without readings)
  double mMedianReading = 0.0;   ///< of a spherical map, the median reading (0 without readings)
  openvdb::BBoxd mReadingBounds;  ///< world box of the reading points
  double mReadingStep = 0.0;
  double mSigma = 0.0;
  double mJumpFactor = 4.0;
  static constexpr double kJumpNoise = 6.0;  ///< sigmas of noise a cell may span on top
  /// The most a usable cell's readings may differ (parallel rays): the
  /// larger of mJumpFactor and kSteepSlopeSpacings pixels, plus the noise.
  double mLargestStep = 0.0;
  double mRayDensity = 1.0;    ///< gamma of an orthographic map: rays per unit area (1 / pixel size^2 by default)
  openvdb::math::Mat4d mMapToWorld = openvdb::math::Mat4d::identity();
  openvdb::math::Mat4d mWorldToMap = openvdb::math::Mat4d::identity();
  openvdb::math::Mat3d mRotation = openvdb::math::Mat3d::identity();  ///< map-to-world rotation
};

// ---- the hot paths of accumulation and carving, inline ----

inline double RangeMap::bilinearReading(std::size_t at, double fu, double fv) const {
  const double r00 = mReadings[at], r10 = mReadings[at + 1];
  const double r01 = mReadings[at + static_cast<std::size_t>(mWidth)];
  const double r11 = mReadings[at + static_cast<std::size_t>(mWidth) + 1];
  return (1 - fv) * ((1 - fu) * r00 + fu * r10) + fv * ((1 - fu) * r01 + fu * r11);
}

inline bool RangeMap::interpolate(double u, double v, double& r, double& ru, double& rv, int& i, int& j, double& fu,
                                  double& fv) const {
  const double border = borderReach();
  // Columns count round the turn: the border before the first lies at the turn's end.
  if (border > 0.0 && u >= mWidth - 1 + border) u -= mProjection.azimuthPeriod();
  if (!(u >= -border) || !(v >= -border) || !(u < mWidth - 1 + border) || !(v < mHeight - 1 + border)) return false;
  // Beyond the border, the cell beside it, extrapolated (fu or fv outside [0, 1]).
  i = std::clamp(static_cast<int>(std::floor(u)), 0, mWidth - 2);
  j = std::clamp(static_cast<int>(std::floor(v)), 0, mHeight - 2);
  const std::size_t at = index(i, j);
  fu = u - i;
  fv = v - j;
  // Never across a missing reading nor a depth discontinuity; a station's
  // surfaces end half a pixel beyond their last rays.
  if (!mUsableCell[at]) return isStation() && extendEdge(i, j, fu, fv, r, ru, rv);
  const double r00 = mReadings[at], r10 = mReadings[at + 1];
  const double r01 = mReadings[at + static_cast<std::size_t>(mWidth)];
  const double r11 = mReadings[at + static_cast<std::size_t>(mWidth) + 1];
  r = bilinearReading(at, fu, fv);
  ru = (1 - fv) * (r10 - r00) + fv * (r11 - r01);
  rv = (1 - fu) * (r01 - r00) + fu * (r11 - r10);
  return true;
}

inline bool RangeMap::outsideBlockWindow(double u, double v, double z, double reach) const {
  if (!(u >= 0.0) || !(v >= 0.0) || !(u < mWidth - 1) || !(v < mHeight - 1)) return false;
  const int i = static_cast<int>(u), j = static_cast<int>(v);
  if (i % kBlock == kBlock - 1 || j % kBlock == kBlock - 1) return false;  // the cell reaches the next block
  const std::size_t b = static_cast<std::size_t>(j / kBlock) * static_cast<std::size_t>(mBlocksX) +
                        static_cast<std::size_t>(i / kBlock);
  // Wider than the exact test's slack by far more than the rounding of an interpolation.
  const double slack = reach * (1.0 + 1e-6) + 1e-6;
  return z < mBlockMin[b] - slack || z > mBlockMax[b] + slack;
}

inline bool RangeMap::sampleLocal(const openvdb::Vec3d& p, double reach, LocalSample& out) const {
  return mProjection.visit([&](const auto& rays) { return sampleLocal(rays, p, reach, out); });
}

inline bool RangeMap::sampleLocal(const ParallelRays& rays, const openvdb::Vec3d& p, double reach,
                                  LocalSample& out) const {
  const openvdb::math::Vec2d uv = rays.pixelByInverse(p);
  const double u = uv.x(), v = uv.y();
  // Far outside the window of the cell's first reading (the others differ
  // from it by less than the discontinuity step): no interpolation needed.
  if (!(u >= 0.0) || !(v >= 0.0) || !(u < mWidth - 1) || !(v < mHeight - 1)) return false;
  const std::size_t at = index(static_cast<int>(u), static_cast<int>(v));
  if (!mUsableCell[at] || std::fabs(p.z() - mReadings[at]) > reach + mLargestStep) return false;
  double r, ru, rv, fu, fv;
  int i, j;
  if (!interpolate(u, v, r, ru, rv, i, j, fu, fv)) return false;
  out.D = p.z() - r;  // Eq. 13, rays along +z
  if (!(std::fabs(out.D) <= reach)) return false;
  out.gradD = openvdb::Vec3d(-ru * rays.inversePixel(), -rv * rays.inversePixel(), 1.0);
  out.gradDSquared = out.gradD.lengthSqr();
  out.lineOfSight = openvdb::Vec3d(0.0, 0.0, 1.0);
  out.gamma = mRayDensity;
  return nearestPixelSays(i, j, fu, fv, out);
}

inline bool RangeMap::sampleLocal(const PinholeRays& rays, const openvdb::Vec3d& p, double reach,
                                  LocalSample& out) const {
  if (!rays.canProject(p)) return false;
  const openvdb::math::Vec2d uv = rays.pixelOf(p);
  if (outsideBlockWindow(uv.x(), uv.y(), p.z(), reach)) return false;
  return sampleLocalAtPixel(rays, p, uv, reach, out);
}

inline bool RangeMap::sampleLocalAtPixel(const PinholeRays& rays, const openvdb::Vec3d& p,
                                         const openvdb::math::Vec2d& uv, double reach, LocalSample& out) const {
  const double u = uv.x(), v = uv.y();
  double r, ru, rv, fu, fv;
  int i, j;
  if (!interpolate(u, v, r, ru, rv, i, j, fu, fv)) return false;
  // D = k (z - r) with k >= 1: a depth farther than the reach from the
  // reading is out of the window (a relative slack leaves ties within
  // rounding to the exact test below).
  if (std::fabs(p.z() - r) > reach * (1.0 + 1e-9)) return false;
  const PinholeProjection& k0 = rays.parameters();
  // Along the ray the reading lies at rho = r k, k = |(a, b, 1)| = |p| / z
  // with (a, b) = (x, y) / z, the slopes of p's ray: D = |p| - rho(u(x), v(x))
  // (Eq. 13). Two reciprocals serve every quotient below.
  const double z = p.z(), distance = p.length();
  const double inverseZ = 1.0 / z, inverseDistance = 1.0 / distance;
  const double a = p.x() * inverseZ, b = p.y() * inverseZ;
  const double k = distance * inverseZ, inverseK = z * inverseDistance;
  out.D = distance - r * k;
  if (!(std::fabs(out.D) <= reach)) return false;
  const double rhoU = ru * k + r * a * inverseK * rays.inverseFx();
  const double rhoV = rv * k + r * b * inverseK * rays.inverseFy();
  out.lineOfSight = p * inverseDistance;
  const double fxOverZ = k0.fx * inverseZ, fyOverZ = k0.fy * inverseZ;
  out.gradD = out.lineOfSight - openvdb::Vec3d(fxOverZ, 0.0, -fxOverZ * a) * rhoU -
              openvdb::Vec3d(0.0, fyOverZ, -fyOverZ * b) * rhoV;
  out.gradDSquared = out.gradD.lengthSqr();
  // Rays per unit area across the line of sight: fx fy / (|p|^2 cos^3) = fx fy k / z^2.
  out.gamma = fxOverZ * fyOverZ * k;
  return nearestPixelSays(i, j, fu, fv, out);
}

inline bool RangeMap::sampleLocal(const SphericalRays& rays, const openvdb::Vec3d& p, double reach,
                                  LocalSample& out) const {
  if (!rays.canProject(p)) return false;  // on the scanner's axis: no azimuth
  const openvdb::math::Vec2d uv = rays.pixelOf(p);
  double r, ru, rv, fu, fv;
  int i, j;
  if (!interpolate(uv.x(), uv.y(), r, ru, rv, i, j, fu, fv)) return false;
  const double distance = p.length();
  out.D = distance - r;  // Eq. 13, along the ray from the scanner
  if (!(std::fabs(out.D) <= reach)) return false;
  // grad D = grad |p| - r_u grad u - r_v grad v, with u and v the azimuth and
  // elevation in steps (the step of the cell's rows).
  const SphericalProjection& grid = rays.parameters();
  const double across2 = p.x() * p.x() + p.y() * p.y(), across = std::sqrt(across2);
  const double distance2 = distance * distance;
  const double elevationStep = rowStep(grid, j);
  const openvdb::Vec3d gradU = openvdb::Vec3d(-p.y(), p.x(), 0.0) / (across2 * grid.azimuthStep);
  const openvdb::Vec3d gradV =
      openvdb::Vec3d(-p.z() * p.x() / across, -p.z() * p.y() / across, across) / (distance2 * elevationStep);
  out.lineOfSight = p / distance;
  out.gradD = out.lineOfSight - gradU * ru - gradV * rv;
  out.gradDSquared = out.gradD.lengthSqr();
  // Rays per unit area across the line of sight: one per solid angle
  // |dtheta dphi| cos(phi), at distance |p|.
  out.gamma = distance / (distance2 * across * std::fabs(grid.azimuthStep * elevationStep));
  return nearestPixelSays(i, j, fu, fv, out);
}

inline bool RangeMap::nearestPixelSays(int i, int j, double fu, double fv, LocalSample& out) const {
  const std::size_t nearest = index(fu < 0.5 ? i : i + 1, fv < 0.5 ? j : j + 1);
  if (!mDirections.empty()) out.lineOfSight = openvdb::Vec3d(mDirections[nearest]);
  out.sigma = sigmaAt(nearest);
  return true;
}

/// Visits range maps one at a time, in their order; a map need not outlive its visit.
using RangeMapVisitor = std::function<void(const RangeMap&)>;
/// A sequence of range maps that can be visited as many times as asked: held
/// in memory, or unpacked (PackedRangeMap) or read one at a time.
using RangeMapSequence = std::function<void(const RangeMapVisitor&)>;
/// The sequence of a vector of range maps (which must outlive it).
RangeMapSequence rangeMapsOf(const std::vector<RangeMap>& maps);
/// Visits range maps one at a time with their numbers in their sequence.
using NumberedRangeMapVisitor = std::function<void(std::size_t index, const RangeMap&)>;
/// A sequence of range maps visited, in order, from the map numbered `first`
/// on (none if there are no more).
using RangeMapsFrom = std::function<void(std::size_t first, const NumberedRangeMapVisitor&)>;
/// The same visits of a sequence (every map is visited to count them).
RangeMapsFrom numberedMapsOf(RangeMapSequence maps);

/// The median of the range maps' noise sigma (world units); throws
/// std::invalid_argument for no maps.
double medianSigma(const std::vector<RangeMap>& maps);

}  // namespace levelfuse

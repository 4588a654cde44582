// levelfuse: range maps.

#include <levelfuse/core/Median.h>
#include <levelfuse/scan/RangeMap.h>

#include "ClampedIndex.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace levelfuse {

namespace {

using openvdb::Vec3d;

void requireRigid(const openvdb::math::Mat4d& m, const std::string& name) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m(i, j))) throw std::invalid_argument(name + ": the pose holds a non-finite number");
  const openvdb::math::Mat3d r = m.getMat3();
  const openvdb::math::Mat3d rtr = r.transpose() * r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (std::fabs(rtr(i, j) - (i == j ? 1.0 : 0.0)) > 1e-4)
        throw std::invalid_argument(name + ": the pose is not a rigid motion (its rotation is not orthonormal)");
  if (r.det() < 0.0) throw std::invalid_argument(name + ": the pose mirrors space (its rotation has determinant -1)");
  if (std::fabs(m(0, 3)) + std::fabs(m(1, 3)) + std::fabs(m(2, 3)) > 1e-9 || std::fabs(m(3, 3) - 1.0) > 1e-9)
    throw std::invalid_argument(name + ": the pose has a projective part (expected OpenVDB's row-vector layout)");
}

}  // namespace

void RangeMap::finish(std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld, double sigma) {
  const std::string who = mName.empty() ? std::string("range map") : "range map '" + mName + "'";
  if (mWidth < 2 || mHeight < 2) throw std::invalid_argument(who + ": needs at least 2 x 2 readings");
  if (readings.size() != static_cast<std::size_t>(mWidth) * static_cast<std::size_t>(mHeight))
    throw std::invalid_argument(who + ": " + std::to_string(readings.size()) + " readings for " +
                                std::to_string(mWidth) + " x " + std::to_string(mHeight) + " pixels");
  if (!(sigma > 0.0) || !std::isfinite(sigma)) throw std::invalid_argument(who + ": sigma must be positive");
  requireRigid(mapToWorld, who);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Depths and ranges (rays from one centre) are positive; parallel rays' z may be anything.
  const bool positive = mProjection.raysFromOneCentre();
  std::size_t valid = 0;
  float largest = 0.0f;
  for (float& r : readings) {
    if (!std::isfinite(r) || (positive && r <= 0.0f)) {
      r = nan;
    } else {
      ++valid;
      largest = std::max(largest, r);
    }
  }
  mValidCount = valid;
  mLargestReading = largest;
  mReadings = std::move(readings);
  if (isStation()) mMedianReading = medianReading();
  mSigma = sigma;
  mBlocksX = (mWidth + kBlock - 1) / kBlock;
  mBlocksY = (mHeight + kBlock - 1) / kBlock;
  findUsableCells();
  findBlockBounds();
  mMapToWorld = mapToWorld;
  mWorldToMap = mapToWorld.inverse();
  mRotation = mapToWorld.getMat3();
  mReadingBounds = boundsOfReadings();
}

void RangeMap::findBlockBounds() {
  const std::size_t blocks = static_cast<std::size_t>(mBlocksX) * static_cast<std::size_t>(mBlocksY);
  const float infinity = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  mBlockMin.assign(blocks, infinity);
  mBlockMax.assign(blocks, -infinity);
  mBlockComplete.assign(blocks, 1);
  for (int v = 0; v < mHeight; ++v) {
    const float* readings = mReadings.data() + index(0, v);
    const std::size_t first = static_cast<std::size_t>(v / kBlock) * static_cast<std::size_t>(mBlocksX);
    for (int b = 0; b < mBlocksX; ++b) {
      float lo = mBlockMin[first + b], hi = mBlockMax[first + b];
      bool complete = true;
      for (int u = b * kBlock; u < std::min((b + 1) * kBlock, mWidth); ++u) {
        const float r = readings[u];
        const bool has = r == r;
        complete &= has;
        lo = std::min(lo, has ? r : infinity);
        hi = std::max(hi, has ? r : -infinity);
      }
      mBlockMin[first + b] = lo;
      mBlockMax[first + b] = hi;
      if (!complete) mBlockComplete[first + b] = 0;
    }
  }
  for (std::size_t b = 0; b < blocks; ++b)
    if (!(mBlockMin[b] <= mBlockMax[b])) mBlockMin[b] = mBlockMax[b] = nan;  // no reading
}

namespace {

/// The sigmas of `count` pixels from `first` (sigmaOf(at)) into `out`; their largest (a function
/// of its own, whose running maximum stays in a register: a lambda's captured one went through memory).
template <typename SigmaOf>
double sigmasOfPixels(const SigmaOf& sigmaOf, std::size_t first, std::size_t count, double* out) {
  double largest = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    out[i] = sigmaOf(first + i);
    largest = std::max(largest, out[i]);
  }
  return largest;
}

}  // namespace

// Inlined into findUsableCells (its only other caller, changesLikeItsNeighbours, is in this file).
inline bool RangeMap::cellReadings(int i, int j, double (&r)[4]) const {
  if (i < 0 || j < 0 || i + 1 >= mWidth || j + 1 >= mHeight) return false;
  const std::size_t at = index(i, j);
  const float readings[4] = {mReadings[at], mReadings[at + 1], mReadings[at + static_cast<std::size_t>(mWidth)],
                             mReadings[at + static_cast<std::size_t>(mWidth) + 1]};
  for (int c = 0; c < 4; ++c) r[c] = readings[c];
  return readings[0] == readings[0] && readings[1] == readings[1] && readings[2] == readings[2] &&
         readings[3] == readings[3];
}

void RangeMap::findUsableCells() {
  mUsableCell = PixelFlags(mReadings.size());
  const std::size_t width = static_cast<std::size_t>(mWidth);
  // The sigmas of the two rows of pixels around a row of cells, each pixel's worked out once.
  std::vector<double> above(width), below(width);
  double largestSigma = mSigma;
  const auto sigmaOfPixel = [this](std::size_t at) { return sigmaAt(at); };
  const auto sigmasOfRow = [&](int j, std::vector<double>& sigmas) {
    largestSigma = std::max(largestSigma, sigmasOfPixels(sigmaOfPixel, index(0, j), width, sigmas.data()));
  };
  // A cell's readings may differ by its four pixels' largest sigma times
  // kJumpNoise: two readings of one surface differ by sqrt(2) sigma typically.
  const auto noiseOfCell = [&](std::size_t i) {
    return kJumpNoise * std::max(std::max(above[i], above[i + 1]), std::max(below[i], below[i + 1]));
  };
  // The cells of a row whose four readings differ by no more than the noise:
  // usable whatever their spacing, which only adds to the bound in front of
  // the rays' start (spansNoDiscontinuity's first rule), found without
  // branches before the others are asked one by one.
  std::vector<std::uint8_t> withinNoise(width);
  const auto cellsWithinNoise = [&](int j) {
    const float* top = mReadings.data() + index(0, j);
    const float* bottom = top + width;
    for (std::size_t i = 0; i + 1 < width; ++i) {
      const float a = top[i], b = top[i + 1], c = bottom[i], d = bottom[i + 1];
      const bool readings = a == a && b == b && c == c && d == d;
      const double lo = std::min(std::min(a, b), std::min(c, d)), hi = std::max(std::max(a, b), std::max(c, d));
      withinNoise[i] = readings & (hi >= 0.0) & (hi - lo <= noiseOfCell(i));
    }
  };
  sigmasOfRow(0, below);
  // The map's kind of rays told apart once, not at every cell.
  mProjection.visit([&](const auto& rays) {
    for (int j = 0; j + 1 < mHeight; ++j) {
      std::swap(above, below);
      sigmasOfRow(j + 1, below);
      cellsWithinNoise(j);
      for (int i = 0; i + 1 < mWidth; ++i) {
        const std::size_t u = static_cast<std::size_t>(i);
        if (withinNoise[u]) {
          mUsableCell.set(index(i, j), true);
          continue;
        }
        double r[4];
        if (!cellReadings(i, j, r)) continue;
        mUsableCell.set(index(i, j), spansNoDiscontinuity(rays, i, j, r, noiseOfCell(u)));
      }
    }
  });
  mLargestStep = std::max(mJumpFactor, kSteepSlopeSpacings) * mProjection.orthographic().pixelSize +
                 kJumpNoise * largestSigma;
}


namespace {

/// How much the readings of a cell (cellReadings' order) change from one
/// column to the next, and from one row to the next: the larger of its two.
double changeAlongColumns(const double (&r)[4]) { return std::max(std::fabs(r[1] - r[0]), std::fabs(r[3] - r[2])); }
double changeAlongRows(const double (&r)[4]) { return std::max(std::fabs(r[2] - r[0]), std::fabs(r[3] - r[1])); }

}  // namespace

template <typename Rays>
bool RangeMap::spansNoDiscontinuity(const Rays& rays, int i, int j, const double (&r)[4], double noise) const {
  const double lo = std::min(std::min(r[0], r[1]), std::min(r[2], r[3]));
  const double hi = std::max(std::max(r[0], r[1]), std::max(r[2], r[3]));
  const double spacing = rays.raySpacingAt(hi);
  if (hi - lo <= mJumpFactor * spacing + noise) return true;
  // Steeper than the factor allows: a surface seen at grazing incidence, if
  // it changes as gradually as the cells beside it.
  return hi - lo <= kSteepSlopeSpacings * spacing + noise && changesLikeItsNeighbours(i, j, r, noise);
}

bool RangeMap::changesLikeItsNeighbours(int i, int j, const double (&r)[4], double noise) const {
  // The neighbours' smaller change on each axis (of those with readings): a
  // step beside a steep surface changes far more than the cell on its other side.
  const double none = std::numeric_limits<double>::infinity();
  double alongColumns = none, alongRows = none;
  double n[4];
  if (cellReadings(i - 1, j, n)) alongColumns = std::min(alongColumns, changeAlongColumns(n));
  if (cellReadings(i + 1, j, n)) alongColumns = std::min(alongColumns, changeAlongColumns(n));
  if (cellReadings(i, j - 1, n)) alongRows = std::min(alongRows, changeAlongRows(n));
  if (cellReadings(i, j + 1, n)) alongRows = std::min(alongRows, changeAlongRows(n));
  if (alongColumns == none || alongRows == none) return false;
  return changeAlongColumns(r) <= kSteepSlopeStepRatio * alongColumns + noise &&
         changeAlongRows(r) <= kSteepSlopeStepRatio * alongRows + noise;
}

void RangeMap::setDiscontinuityFactor(double factor) {
  if (!(factor > 0.0)) throw std::invalid_argument("range map '" + mName + "': the discontinuity factor must be positive");
  mJumpFactor = factor;
  findUsableCells();
}

RangeMap RangeMap::orthographic(int width, int height, std::vector<float> readings, const OrthographicProjection& p,
                                const openvdb::math::Mat4d& mapToWorld, double sigma, std::string name) {
  if (!(p.pixelSize > 0.0) || !std::isfinite(p.pixelSize) || !std::isfinite(p.origin.x()) ||
      !std::isfinite(p.origin.y()))
    throw std::invalid_argument("range map '" + name + "': the pixel size must be positive and finite");
  RangeMap m(MapProjection(p), width, height, std::move(name));
  const double inversePixel = m.mProjection.parallelRays().inversePixel();
  m.mRayDensity = inversePixel * inversePixel;
  m.finish(std::move(readings), mapToWorld, sigma);
  return m;
}

namespace {

/// Uneven rows' elevations checked (one per row), and the grid's elevation
/// start and step taken from them: the first and the mean spacing.
void takeRowElevations(SphericalProjection& p, int height, const std::string& who) {
  const std::vector<double>& rows = p.rowElevations;
  if (rows.size() != static_cast<std::size_t>(height))
    throw std::invalid_argument(who + ": " + std::to_string(rows.size()) + " row elevations for " +
                                std::to_string(height) + " rows");
  requireRowElevations(rows, who);
  p.elevationStart = rows.front();
  p.elevationStep = (rows.back() - rows.front()) / static_cast<double>(height - 1);
}

}  // namespace

RangeMap RangeMap::sphericalWithoutReadings(int width, int height, SphericalProjection p, std::string name) {
  const std::string who = "range map '" + name + "'";
  if (!p.rowElevations.empty()) takeRowElevations(p, height, who);
  if (!std::isfinite(p.azimuthStart) || !std::isfinite(p.elevationStart) || !std::isfinite(p.azimuthStep) ||
      !std::isfinite(p.elevationStep) || p.azimuthStep == 0.0 || p.elevationStep == 0.0)
    throw std::invalid_argument(who + ": the angular steps must be finite and not zero");
  const double lastElevation = p.elevationStart + (height - 1) * p.elevationStep;
  if (!(std::fabs(p.elevationStart) < 0.5 * M_PI) || !(std::fabs(lastElevation) < 0.5 * M_PI))
    throw std::invalid_argument(who + ": its rows reach a pole (elevations from " +
                                std::to_string(p.elevationStart * 180.0 / M_PI) + " to " +
                                std::to_string(lastElevation * 180.0 / M_PI) + " degrees)");
  // A closed turn repeats its first column after its last: one step more than a turn.
  if ((width - 1) * std::fabs(p.azimuthStep) > 2.0 * M_PI * (1.0 + 1e-9))
    throw std::invalid_argument(who + ": its " + std::to_string(width) + " columns span more than a turn");
  return RangeMap(MapProjection(std::move(p)), width, height, std::move(name));
}

RangeMap RangeMap::spherical(int width, int height, std::vector<float> ranges, const SphericalProjection& p,
                             const openvdb::math::Mat4d& scannerToWorld, double sigma, std::string name) {
  return finished(sphericalWithoutReadings(width, height, p, std::move(name)), std::move(ranges), scannerToWorld,
                  sigma);
}

RangeMap RangeMap::spherical(int width, int height, std::vector<float> ranges, const SphericalProjection& p,
                             const openvdb::math::Mat4d& scannerToWorld, const DepthNoise& noise, std::string name) {
  return finished(sphericalWithoutReadings(width, height, p, std::move(name)), std::move(ranges), scannerToWorld,
                  noise);
}

RangeMap RangeMap::finished(RangeMap m, std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld,
                            double sigma) {
  m.finish(std::move(readings), mapToWorld, sigma);
  return m;
}

RangeMap RangeMap::finished(RangeMap m, std::vector<float> readings, const openvdb::math::Mat4d& mapToWorld,
                            const DepthNoise& noise) {
  m.adoptDepthNoise(noise);
  m.finish(std::move(readings), mapToWorld, noise.at(1.0));
  return m;
}

RangeMap RangeMap::pinholeWithoutReadings(int width, int height, const PinholeProjection& p, std::string name) {
  if (!(p.fx > 0.0) || !(p.fy > 0.0) || !std::isfinite(p.fx) || !std::isfinite(p.fy) || !std::isfinite(p.cx) ||
      !std::isfinite(p.cy))
    throw std::invalid_argument("range map '" + name + "': focal lengths must be positive and finite");
  // The lines of sight of a pinhole fan out within a half-space: focal lengths
  // so short that the image spans nearly 180 degrees (a thousandth of a pixel)
  // are not a camera's, and would send its readings' windows out for ever.
  const auto span = [](double lo, double hi, double f) { return std::atan(hi / f) - std::atan(lo / f); };
  const double degrees =
      180.0 / M_PI * std::max(span(-p.cx, width - 1 - p.cx, p.fx), span(-p.cy, height - 1 - p.cy, p.fy));
  if (degrees >= kWidestPinholeView) {
    char text[240];
    std::snprintf(text, sizeof(text),
                  "focal lengths of %.3g x %.3g pixels give a %d x %d image a field of view of %.6g degrees, more "
                  "than the %.0f of a pinhole camera (focal lengths are in pixels, a Kinect's about 585)",
                  p.fx, p.fy, width, height, degrees, kWidestPinholeView);
    throw std::invalid_argument("range map '" + name + "': " + text);
  }
  return RangeMap(MapProjection(p), width, height, std::move(name));
}

RangeMap RangeMap::pinhole(int width, int height, std::vector<float> depths, const PinholeProjection& p,
                           const openvdb::math::Mat4d& cameraToWorld, double sigma, std::string name) {
  return finished(pinholeWithoutReadings(width, height, p, std::move(name)), std::move(depths), cameraToWorld, sigma);
}

RangeMap RangeMap::pinhole(int width, int height, std::vector<float> depths, const PinholeProjection& p,
                           const openvdb::math::Mat4d& cameraToWorld, const DepthNoise& noise, std::string name) {
  return finished(pinholeWithoutReadings(width, height, p, std::move(name)), std::move(depths), cameraToWorld, noise);
}

void RangeMap::setRayDirections(std::vector<openvdb::Vec3f> directions) {
  if (directions.size() != mReadings.size())
    throw std::invalid_argument("range map '" + mName + "': one ray direction per pixel is needed");
  for (openvdb::Vec3f& d : directions) {
    const float length = d.length();
    if (!(length > 0.0f) || !std::isfinite(length))
      throw std::invalid_argument("range map '" + mName + "': a ray direction is zero or not finite");
    d /= length;
  }
  mDirections = std::move(directions);
}

void RangeMap::setSigmas(std::vector<float> sigmas) {
  if (sigmas.size() != mReadings.size())
    throw std::invalid_argument("range map '" + mName + "': one sigma per pixel is needed");
  for (float s : sigmas)
    if (!(s > 0.0f) || !std::isfinite(s))
      throw std::invalid_argument("range map '" + mName + "': sigmas must be positive and finite");
  mSigmas = std::move(sigmas);
  mHasDepthNoise = false;
  findUsableCells();
}

void RangeMap::setColours(std::vector<Rgb8> colours) {
  if (!colours.empty() && colours.size() != mReadings.size())
    throw std::invalid_argument("range map '" + mName + "': one colour per pixel is needed");
  mColours = std::move(colours);
}

template <typename Visit>
void RangeMap::forEachUsableCellAt(int u, int v, const Visit& visit) const {
  for (int a = u - 1; a <= u; ++a)
    for (int b = v - 1; b <= v; ++b)
      if (a >= 0 && b >= 0 && a + 1 < mWidth && b + 1 < mHeight && mUsableCell[index(a, b)]) visit(a, b);
}

bool RangeMap::extendableCorner(int u, int v) const {
  const float reading = mReadings[index(u, v)];
  if (!(reading == reading)) return false;
  bool corner = false;
  forEachUsableCellAt(u, v, [&](int, int) { corner = true; });
  return corner;
}

double RangeMap::edgeExtensionReach(double reading) const {
  // Half a pixel along each direction at the steepest slope.
  return isStation() ? kSteepestEdgeSlope * mProjection.raySpacingAt(reading) : 0.0;
}

bool RangeMap::usableCellSpan(int i, int j, float& lo, float& hi) const {
  if (!mUsableCell[index(i, j)]) return false;
  const double border = borderReach();
  // A bilinear reading is extreme at the corners of the stretch it covers.
  const double u0 = i == 0 ? -border : 0.0, u1 = i + 2 == mWidth ? 1.0 + border : 1.0;
  const double v0 = j == 0 ? -border : 0.0, v1 = j + 2 == mHeight ? 1.0 + border : 1.0;
  const std::size_t at = index(i, j);
  lo = std::numeric_limits<float>::max();
  hi = -lo;
  for (const double fu : {u0, u1})
    for (const double fv : {v0, v1}) {
      const auto r = static_cast<float>(bilinearReading(at, fu, fv));
      lo = std::min(lo, r);
      hi = std::max(hi, r);
    }
  return true;
}

bool RangeMap::edgeReadings(int i, int j, float& lo, float& hi) const {
  if (!isStation() || mUsableCell[index(i, j)]) return false;
  lo = std::numeric_limits<float>::max();
  hi = -lo;
  for (int c = 0; c < 4; ++c) {
    const int u = i + (c & 1), v = j + (c >> 1);
    if (!extendableCorner(u, v)) continue;
    const double reading = mReadings[index(u, v)], reach = edgeExtensionReach(reading);
    lo = std::min(lo, static_cast<float>(reading - reach));
    hi = std::max(hi, static_cast<float>(reading + reach));
  }
  return lo <= hi;
}

bool RangeMap::extendEdge(int i, int j, double& fu, double& fv, double& r, double& ru, double& rv) const {
  const int cornerU = fu < 0.5 ? 0 : 1, cornerV = fv < 0.5 ? 0 : 1;
  const int pu = i + cornerU, pv = j + cornerV;
  if (!extendableCorner(pu, pv)) return false;
  const double reading = mReadings[index(pu, pv)];
  // The slopes along u and v of the usable cells around the pixel, on the
  // edges that meet at it.
  double slopeU = 0.0, slopeV = 0.0;
  int cells = 0;
  forEachUsableCellAt(pu, pv, [&](int a, int b) {
    slopeU += mReadings[index(a + 1, pv)] - mReadings[index(a, pv)];
    slopeV += mReadings[index(pu, b + 1)] - mReadings[index(pu, b)];
    ++cells;
  });
  // Near a convex object's limb the ranges fall away without bound: the half
  // pixel beyond the last ray follows the surface no steeper than this.
  const double steepest = kSteepestEdgeSlope * mProjection.raySpacingAt(reading);
  ru = std::clamp(slopeU / cells, -steepest, steepest);
  rv = std::clamp(slopeV / cells, -steepest, steepest);
  r = reading + ru * (fu - cornerU) + rv * (fv - cornerV);
  fu = cornerU;
  fv = cornerV;
  return true;
}

bool RangeMap::colourAt(const openvdb::Vec3d& p, openvdb::Vec3f& rgb) const {
  if (mColours.empty() || !canProject(p)) return false;
  const openvdb::math::Vec2d uv = project(p);
  double r, ru, rv, fu, fv;
  int i, j;
  if (!interpolate(uv.x(), uv.y(), r, ru, rv, i, j, fu, fv)) return false;
  fu = std::clamp(fu, 0.0, 1.0);  // beyond the border, the border's colours
  fv = std::clamp(fv, 0.0, 1.0);
  const std::size_t at = index(i, j), below = at + static_cast<std::size_t>(mWidth);
  const double corner[4] = {(1 - fu) * (1 - fv), fu * (1 - fv), (1 - fu) * fv, fu * fv};
  const std::size_t pixel[4] = {at, at + 1, below, below + 1};
  openvdb::Vec3d sum(0.0);
  for (int k = 0; k < 4; ++k) {
    const Rgb8& c = mColours[pixel[k]];
    sum += openvdb::Vec3d(c[0], c[1], c[2]) * corner[k];
  }
  rgb = openvdb::Vec3f(sum / 255.0);
  return true;
}

void RangeMap::adoptDepthNoise(const DepthNoise& noise) {
  if (!(noise.minimum > 0.0) || !std::isfinite(noise.minimum) || !(noise.perSquareMetre >= 0.0) ||
      !std::isfinite(noise.perSquareMetre) || !(noise.perMetre >= 0.0) || !std::isfinite(noise.perMetre))
    throw std::invalid_argument("range map '" + mName + "': the depth noise must be positive and finite");
  mSigmas.clear();
  mSigmas.shrink_to_fit();
  mDepthNoise = noise;
  mHasDepthNoise = true;
}

void RangeMap::setDepthNoise(const DepthNoise& noise) {
  adoptDepthNoise(noise);
  findUsableCells();
}

void RangeMap::setSamples(std::vector<openvdb::Vec3d> worldPoints, double raySpacing) {
  if (raysFromOneCentre())
    throw std::invalid_argument("range map '" + mName + "': only an orthographic map is resampled from samples");
  if (!(raySpacing > 0.0) || !std::isfinite(raySpacing))
    throw std::invalid_argument("range map '" + mName + "': the samples' ray spacing must be positive");
  for (const Vec3d& p : worldPoints)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw std::invalid_argument("range map '" + mName + "': a sample point is not finite");
  mSamples = std::move(worldPoints);
  mRayDensity = 1.0 / (raySpacing * raySpacing);
}

void RangeMap::letSamplesGo() {
  if (mSamples.empty()) return;
  mSamplesLetGo = mSamples.size();
  std::vector<openvdb::Vec3d>().swap(mSamples);
}

void RangeMap::setReadingStep(double step) {
  if (!(step >= 0.0) || !std::isfinite(step))
    throw std::invalid_argument("range map '" + mName + "': the step of the readings must be finite and not negative");
  mReadingStep = step;
}

void RangeMap::setMissesAreEmpty(bool empty, int dropoutReach) {
  if (dropoutReach < 0) throw std::invalid_argument("range map '" + mName + "': negative dropout reach");
  mMisses.clear();
  mDropoutReach = dropoutReach;
  if (!empty) return;
  mMisses = PixelFlags(mReadings.size());
  for (int v = 0; v < mHeight; ++v)
    for (int u = 0; u < mWidth; ++u) {
      bool nearReading = false;
      for (int j = std::max(0, v - dropoutReach); j <= std::min(mHeight - 1, v + dropoutReach) && !nearReading; ++j)
        for (int i = std::max(0, u - dropoutReach); i <= std::min(mWidth - 1, u + dropoutReach); ++i)
          if (valid(i, j)) {
            nearReading = true;
            break;
          }
      mMisses.set(index(u, v), !nearReading);
    }
}

// Inlined into sight() and the loop of sights(), carving's hot path.
inline RangeMap::Sight RangeMap::sightAtPixel(double u, double v, double along, double margin) const {
  if (!(u >= 0.0 && v >= 0.0 && u <= mWidth - 1 && v <= mHeight - 1)) return Sight::kOutside;
  const int i = std::min(static_cast<int>(u), mWidth - 2), j = std::min(static_cast<int>(v), mHeight - 2);
  // Where the data term interpolates, the reading it interpolates (Eq. 13's
  // r_j(x)) decides: no point is left unknown between the window's reach and
  // the carved space, where a surface seen at grazing incidence would settle
  // inside.
  if (mUsableCell[index(i, j)]) {
    const double D = along - bilinearReading(index(i, j), u - i, v - j);
    return D < -margin ? Sight::kEmpty : D > margin ? Sight::kBehind : Sight::kUnknown;
  }
  // Elsewhere the four pixels around x must agree: near a depth discontinuity
  // or a silhouette the nearest ray alone could pass either side of x.
  const bool missesAreEmpty = !mMisses.empty();
  int empty = 0, behind = 0;
  for (int c = 0; c < 4; ++c) {
    const std::size_t at = index(i + (c & 1), j + (c >> 1));
    const float r = mReadings[at];
    // Along the rays (parallel), the optical axis (pinhole) or the ray
    // (spherical); NaN where the pixel has no reading, neither in front nor
    // behind (no branch on the holes, which come and go from pixel to pixel).
    const double D = along - r;
    empty += D < -margin;
    behind += D > margin;
    if (missesAreEmpty && !(r == r)) empty += mMisses[at];
  }
  if (empty == 4) return Sight::kEmpty;
  if (behind == 4) return Sight::kBehind;
  return Sight::kUnknown;
}

RangeMap::Sight RangeMap::sight(const Vec3d& x, double margin) const {
  const Vec3d p = mWorldToMap.transform(x);
  if (!canProject(p)) return Sight::kOutside;
  const openvdb::math::Vec2d uv = project(p);
  return sightAtPixel(uv.x(), uv.y(), readingCoordinate(p), margin);
}

void RangeMap::sights(const Vec3d* x, std::size_t count, double margin, Sight* out) const {
  mProjection.visit([&](const auto& rays) {
    // The projections of a batch of points first, as sight() works them out,
    // then their readings.
    constexpr std::size_t kBatch = 64;
    double u[kBatch], v[kBatch], along[kBatch];
    bool seen[kBatch];
    for (std::size_t first = 0; first < count; first += kBatch) {
      const std::size_t n = std::min(kBatch, count - first);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3d p = mWorldToMap.transform(x[first + i]);
        const openvdb::math::Vec2d uv = rays.pixelOf(p);
        seen[i] = rays.canProject(p);
        u[i] = uv.x();
        v[i] = uv.y();
        along[i] = rays.readingOf(p);
      }
      for (std::size_t i = 0; i < n; ++i)
        out[first + i] = seen[i] ? sightAtPixel(u[i], v[i], along[i], margin) : Sight::kOutside;
    }
  });
}

bool RangeMap::mayBeSeenIn(const openvdb::BBoxd& box) const {
  if (!mProjection.keepsLinesStraight()) return true;
  // A camera's projection of a box wholly in front of it is the hull of its
  // corners' projections (parallel rays': always); sightAtPixel sees the
  // pixels' span [0, width - 1] x [0, height - 1].
  double u0 = HUGE_VAL, v0 = HUGE_VAL, u1 = -HUGE_VAL, v1 = -HUGE_VAL;
  int inFront = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3d x((corner & 1) ? box.max().x() : box.min().x(), (corner & 2) ? box.max().y() : box.min().y(),
                  (corner & 4) ? box.max().z() : box.min().z());
    const Vec3d p = mWorldToMap.transform(x);
    if (!canProject(p)) continue;  // behind the camera (a station's were answered above)
    ++inFront;
    const openvdb::math::Vec2d uv = project(p);
    u0 = std::min(u0, uv.x());
    v0 = std::min(v0, uv.y());
    u1 = std::max(u1, uv.x());
    v1 = std::max(v1, uv.y());
  }
  if (inFront == 0) return false;  // wholly behind the camera
  if (inFront < 8) return true;    // across the camera's plane: its projection is unbounded
  return !(u1 < 0.0 || v1 < 0.0 || u0 > mWidth - 1 || v0 > mHeight - 1);
}

bool RangeMap::missesBall(const Vec3d& centre, double radius) const {
  const Vec3d c = mWorldToMap.transform(centre);  // the pose is rigid: the ball keeps its radius
  // Ties within rounding go to the points: sight() projects each on its own.
  const double slack = 1e-9 * (c.length() + radius);
  return mProjection.missesBall(c, radius, mWidth, mHeight, slack);
}

bool RangeMap::readingBounds(double u0, double v0, double u1, double v1, double& lo, double& hi,
                             bool* complete) const {
  if (!(u1 >= 0.0) || !(v1 >= 0.0) || !(u0 <= mWidth - 1) || !(v0 <= mHeight - 1)) return false;
  const int b0 = detail::clampedIndex(std::floor(u0), mWidth - 1) / kBlock, b1 = detail::clampedIndex(std::ceil(u1), mWidth - 1) / kBlock;
  const int c0 = detail::clampedIndex(std::floor(v0), mHeight - 1) / kBlock;
  const int c1 = detail::clampedIndex(std::ceil(v1), mHeight - 1) / kBlock;
  bool any = false;
  lo = std::numeric_limits<double>::max();
  hi = -lo;
  if (complete) *complete = true;
  for (int c = c0; c <= c1; ++c)
    for (int b = b0; b <= b1; ++b) {
      const std::size_t at = static_cast<std::size_t>(c) * mBlocksX + b;
      if (complete && !mBlockComplete[at]) *complete = false;
      if (!(mBlockMin[at] == mBlockMin[at])) continue;
      lo = std::min(lo, static_cast<double>(mBlockMin[at]));
      hi = std::max(hi, static_cast<double>(mBlockMax[at]));
      any = true;
    }
  return any;
}

bool RangeMap::sample(const openvdb::Vec3d& x, RangeSample& out) const {
  LocalSample s;
  if (!sampleLocal(mWorldToMap.transform(x), std::numeric_limits<double>::infinity(), s)) return false;
  out.D = s.D;
  out.gradD = mMapToWorld.transform3x3(s.gradD);
  out.lineOfSight = mMapToWorld.transform3x3(s.lineOfSight);
  out.gamma = s.gamma;
  out.sigma = s.sigma;
  return true;
}

openvdb::Vec3d RangeMap::readingPoint(int u, int v) const { return pointAt(u, v, mReadings[index(u, v)]); }

openvdb::Vec3d RangeMap::pointAt(double u, double v, double r) const {
  return mMapToWorld.transform(mProjection.pointAt(u, v, r));
}

bool RangeMap::ofAScene() const { return raysFromOneCentre(); }

openvdb::Vec3d RangeMap::scannerPosition() const {
  if (raysFromOneCentre()) return mMapToWorld.transform(Vec3d(0.0));
  const OrthographicProjection& lattice = mProjection.orthographic();
  double zmin = std::numeric_limits<double>::max();
  for (float r : mReadings)
    if (r == r) zmin = std::min(zmin, static_cast<double>(r));
  const double extent = std::max(mWidth, mHeight) * lattice.pixelSize;
  const Vec3d centre(lattice.origin.x() + 0.5 * (mWidth - 1) * lattice.pixelSize,
                     lattice.origin.y() + 0.5 * (mHeight - 1) * lattice.pixelSize,
                     (zmin == std::numeric_limits<double>::max() ? 0.0 : zmin) - 10.0 * extent);
  return mMapToWorld.transform(centre);
}

double RangeMap::medianReading() const {
  std::vector<float> valid;
  valid.reserve(mValidCount);
  for (float r : mReadings)
    if (r == r) valid.push_back(r);
  if (valid.empty()) return 0.0;
  const auto middle = valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2);
  std::nth_element(valid.begin(), middle, valid.end());
  return *middle;
}

double RangeMap::typicalRaySpacing() const {
  if (!isStation()) return maxRaySpacing();
  const SphericalProjection& grid = mProjection.spherical();
  return mMedianReading * std::sqrt(std::fabs(grid.azimuthStep) * std::fabs(grid.elevationStep));
}

double RangeMap::maxRaySpacing() const {
  // Parallel rays: the scanner's spacing, where the map was resampled from its samples.
  if (!raysFromOneCentre()) return 1.0 / std::sqrt(mRayDensity);
  return mProjection.raySpacingAt(mLargestReading);
}

template <typename Rays, typename Visit>
void RangeMap::forEachReadingPoint(const Rays& rays, const Visit& visit) const {
  for (int v = 0; v < mHeight; ++v) {
    const float* readings = mReadings.data() + index(0, v);
    for (int u = 0; u < mWidth; ++u)
      if (readings[u] == readings[u]) visit(mMapToWorld.transform(rays.pointAt(u, v, readings[u])));
  }
}

template <typename Visit>
void RangeMap::forEachReadingPoint(const PinholeRays& rays, const Visit& visit) const {
  // PinholeRays::pointAt's arithmetic, each column's and row's slope worked out once.
  std::vector<double> columnSlopes(static_cast<std::size_t>(mWidth));
  for (int u = 0; u < mWidth; ++u) columnSlopes[static_cast<std::size_t>(u)] = rays.columnSlope(u);
  for (int v = 0; v < mHeight; ++v) {
    const float* readings = mReadings.data() + index(0, v);
    const double rowSlope = rays.rowSlope(v);
    for (int u = 0; u < mWidth; ++u)
      if (readings[u] == readings[u])
        visit(mMapToWorld.transform(
            PinholeRays::pointOnRay(columnSlopes[static_cast<std::size_t>(u)], rowSlope, readings[u])));
  }
}

openvdb::BBoxd RangeMap::boundsOfReadings() const {
  // Held apart from the box while the points are visited, so that they stay in registers.
  const double none = std::numeric_limits<double>::max();
  double x0 = none, y0 = none, z0 = none, x1 = -none, y1 = -none, z1 = -none;
  mProjection.visit([&](const auto& rays) {
    forEachReadingPoint(rays, [&](const Vec3d& x) {
      x0 = std::min(x0, x.x());
      y0 = std::min(y0, x.y());
      z0 = std::min(z0, x.z());
      x1 = std::max(x1, x.x());
      y1 = std::max(y1, x.y());
      z1 = std::max(z1, x.z());
    });
  });
  return openvdb::BBoxd(Vec3d(x0, y0, z0), Vec3d(x1, y1, z1));
}

std::size_t RangeMap::memoryBytes() const {
  return sizeof(*this) + mName.capacity() + mBlockMin.capacity() * sizeof(float) +
         mBlockMax.capacity() * sizeof(float) + mBlockComplete.capacity() +
         mReadings.capacity() * sizeof(float) +
         mUsableCell.memoryBytes() + mDirections.capacity() * sizeof(openvdb::Vec3f) +
         mSigmas.capacity() * sizeof(float) + mColours.capacity() * sizeof(Rgb8) + mSamples.capacity() * sizeof(openvdb::Vec3d) + mMisses.memoryBytes();
}

RangeMapSequence rangeMapsOf(const std::vector<RangeMap>& maps) {
  return [&maps](const RangeMapVisitor& visit) {
    for (const RangeMap& m : maps) visit(m);
  };
}

RangeMapsFrom numberedMapsOf(RangeMapSequence maps) {
  return [maps = std::move(maps)](std::size_t first, const NumberedRangeMapVisitor& visit) {
    std::size_t index = 0;
    maps([&](const RangeMap& m) {
      if (index >= first) visit(index, m);
      ++index;
    });
  };
}

double medianSigma(const std::vector<RangeMap>& maps) {
  if (maps.empty()) throw std::invalid_argument("medianSigma: no range maps");
  std::vector<double> sigmas;
  for (const RangeMap& m : maps) sigmas.push_back(m.sigma());
  return median(std::move(sigmas));
}

}  // namespace levelfuse

// Surfaces that spherical scanners see at grazing incidence come back where
// they are, not inside them: the readings of a steep smooth surface are
// interpolated (RangeMap's usable cells, Eqs. 13, 17) and space carving
// decides with the reading the data term interpolates.

#include <levelfuse/geometry/Shapes.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/synth/Synth.h>

#include <openvdb/tools/Interpolation.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace levelfuse {
namespace {

using openvdb::Vec3d;

constexpr double kDegree = M_PI / 180.0;
constexpr double kVoxel = 0.01;

/// Signed errors (world units, positive outside) of a surface's points whose
/// incidence falls in [from, to) degrees.
struct IncidenceBand {
  double from = 0.0, to = 90.0;
  double sum = 0.0, sumSquares = 0.0;
  std::size_t points = 0;
  double mean() const { return points ? sum / static_cast<double>(points) : 0.0; }
  double rms() const { return points ? std::sqrt(sumSquares / static_cast<double>(points)) : 0.0; }
};

/// What a test needs of its true surface at a point of the reconstruction:
/// its signed distance to the surface and the surface's outward normal at
/// the nearest point.
struct Truth {
  std::function<double(const Vec3d&)> distance;
  std::function<Vec3d(const Vec3d&)> normal;
};

/// The smallest angle (degrees) between the true surface's normal at `onSurface`
/// and the lines of sight of the scanners at `eyes` that face it; 180 if none does.
double bestIncidence(const Vec3d& onSurface, const Vec3d& normal, const std::vector<Vec3d>& eyes) {
  double best = -1.0;
  for (const Vec3d& eye : eyes) best = std::max(best, -(onSurface - eye).unit().dot(normal));
  return best > 0.0 ? std::acos(std::min(best, 1.0)) / kDegree : 180.0;
}

/// The signed errors of the zero crossings of `surface` within 5 cm of the
/// true surface and facing as it does (its level set rising along the true
/// normal) where `counts` holds, by the incidence of the best scanner at `eyes`.
std::vector<IncidenceBand> errorsByIncidence(const openvdb::FloatGrid& surface, const Truth& truth,
                                             const std::vector<Vec3d>& eyes, std::vector<IncidenceBand> bands,
                                             const std::function<bool(const Vec3d&)>& counts) {
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> phi(surface);
  for (const Vec3d& p : zeroCrossings(surface)) {
    const double d = truth.distance(p);
    if (std::fabs(d) > 0.05 || !counts(p)) continue;
    const Vec3d n = truth.normal(p);
    // A face of the surface turned away from the true one (the solid's sides
    // or underside) rises by less than half a voxel per voxel along its normal.
    if (!(phi.wsSample(p + n * kVoxel) - phi.wsSample(p - n * kVoxel) > kVoxel)) continue;
    const double incidence = bestIncidence(p - n * d, n, eyes);
    for (IncidenceBand& band : bands)
      if (incidence >= band.from && incidence < band.to) {
        band.sum += d;
        band.sumSquares += d * d;
        ++band.points;
      }
  }
  return bands;
}

void print(const std::string& what, const std::vector<IncidenceBand>& bands) {
  std::printf("%s\n| incidence (degrees) | mean (mm) | rms (mm) | points |\n| --- | --- | --- | --- |\n", what.c_str());
  for (const IncidenceBand& b : bands)
    std::printf("| %g-%g | %+.2f | %.2f | %zu |\n", b.from, b.to, 1000.0 * b.mean(), 1000.0 * b.rms(), b.points);
}

/// The surface within 1 mm on average and 2 mm rms of the truth in every band.
void expectOnTheSurface(const std::vector<IncidenceBand>& bands) {
  for (const IncidenceBand& b : bands) {
    ASSERT_GT(b.points, 100u) << b.from << "-" << b.to << " degrees";
    EXPECT_GT(b.mean(), -0.001) << b.from << "-" << b.to << " degrees: inside on average";
    EXPECT_LT(b.mean(), 0.001) << b.from << "-" << b.to << " degrees: outside on average";
    EXPECT_LT(b.rms(), 0.002) << b.from << "-" << b.to << " degrees";
  }
}

/// The settings the converter derives for these scans, given: 1 cm voxels,
/// the window and the prior of 2 mm noise.
ReconstructionOptions centimetreOptions(int levels) {
  ReconstructionOptions options;
  options.voxelSize = kVoxel;
  options.levels = levels;
  options.epsilon = 0.002;
  options.beta = 0.5;
  return options;
}

/// A floor (z = 0) seen from a tripod 0.5 m above it, its azimuths 8 degrees
/// either side of +x and its elevations those that meet the floor at
/// incidences from `nearest` to `farthest` degrees, 0.1 degrees apart, with
/// Gaussian range noise `noise`.
RangeMap floorScan(double nearest, double farthest, double noise, const Vec3d& eye) {
  const double lowest = -(90.0 - nearest), highest = -(90.0 - farthest);
  const synth::View view = synth::sphericalView(eye, -8.0, 8.0, lowest, highest, 0.1, "floor");
  synth::Noise gaussian;
  gaussian.gaussianSigma = noise;
  return synth::renderDistanceFunction([](const Vec3d& p) { return p.z(); }, view, gaussian, 0.002);
}

/// The floor's points 5 cm or more from the edges of the part of it that a
/// scan from `eye` (floorScan) sees, at incidences from `nearest` to
/// `farthest` degrees.
std::function<bool(const Vec3d&)> awayFromTheEdges(const Vec3d& eye, double nearest, double farthest) {
  const double nearEnd = eye.z() * std::tan(nearest * kDegree), farEnd = eye.z() * std::tan(farthest * kDegree);
  return [=](const Vec3d& p) {
    const Vec3d q = p - eye;
    const double away = std::hypot(q.x(), q.y());
    const double fromTheSides = away * std::sin(8.0 * kDegree - std::fabs(std::atan2(q.y(), q.x())));
    return fromTheSides > 0.05 && away > nearEnd + 0.05 && away < farEnd - 0.05;
  };
}

const Truth kFloor{[](const Vec3d& p) { return p.z(); }, [](const Vec3d&) { return Vec3d(0.0, 0.0, 1.0); }};

/// A floor seen from a tripod 0.5 m above it at incidences from `nearest`
/// to `farthest` degrees with 2 mm of noise, reconstructed on `levels`
/// grids: within 1 mm on average and 2 mm rms of itself in each of `bands`.
void expectTheFloorBack(double nearest, double farthest, int levels, std::vector<IncidenceBand> bands) {
  const Vec3d eye(0.0, 0.0, 0.5);
  const std::vector<RangeMap> maps{floorScan(nearest, farthest, 0.002, eye)};
  const ReconstructionResult result = Reconstructor(maps, centimetreOptions(levels)).run();
  bands = errorsByIncidence(*result.levelSet, kFloor, {eye}, std::move(bands),
                            awayFromTheEdges(eye, nearest, farthest));
  print("a floor from one tripod 0.5 m above it", bands);
  expectOnTheSurface(bands);
}

TEST(GrazingIncidence, AFloorAtEightyDegreesComesBackOnItself) {
  // The incidences from 72 to 85 degrees, 2 mm of noise: from about 76
  // degrees on, a cell's readings spread over more than four ray spacings
  // plus six sigma.
  expectTheFloorBack(72.0, 85.0, 1, {{72.0, 80.0}, {80.0, 85.0}});
}

TEST(GrazingIncidence, AFloorFromSixtyToEightyOneDegreesComesBackOnItself) {
  expectTheFloorBack(60.0, 81.0, 3, {{60.0, 72.0}, {72.0, 80.0}, {80.0, 85.0}});
}

TEST(GrazingIncidence, ASphereFromTwoTripodsComesBackOnItselfUpToEightyDegrees) {
  // A ball of radius 0.5 m from tripods 2.5 m away on either side, 0.25
  // degrees between rays (1.1 cm at the ball) and 2 mm of range noise.
  const shapes::Sphere ball{Vec3d(0.0), 0.5};
  const std::vector<Vec3d> eyes{Vec3d(2.5, 0.0, 0.0), Vec3d(-2.5, 0.0, 0.0)};
  std::vector<RangeMap> maps;
  for (std::size_t k = 0; k < eyes.size(); ++k) {
    const double toward = k == 0 ? 180.0 : 0.0;  // the azimuth of the ball's centre
    const synth::View view = synth::sphericalView(eyes[k], toward - 13.25, toward + 13.25, -13.25, 13.25, 0.25,
                                                  "tripod " + std::to_string(k));
    synth::Noise gaussian;
    gaussian.gaussianSigma = 0.002;
    gaussian.seed = k + 1;
    maps.push_back(synth::renderDistanceFunction(ball, view, gaussian, 0.002));
  }
  const ReconstructionResult result = Reconstructor(maps, centimetreOptions(2)).run();
  const Truth truth{ball, [](const Vec3d& p) { return p.unit(); }};
  const std::vector<IncidenceBand> bands = errorsByIncidence(
      *result.levelSet, truth, eyes, {{0.0, 53.0}, {53.0, 72.0}, {72.0, 80.0}}, [](const Vec3d&) { return true; });
  print("a sphere from two tripods", bands);
  expectOnTheSurface(bands);
}

}  // namespace
}  // namespace levelfuse

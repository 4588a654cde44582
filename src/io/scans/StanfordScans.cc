// levelfuse: Stanford range scans and their .conf placements.

#include <levelfuse/core/Median.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/TextRecords.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/scan/DepthRaster.h>

#include "FrameAlong.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <limits>
#include <utility>

namespace levelfuse::io {

namespace fs = std::filesystem;
using openvdb::Vec3d;
using Mat4d = openvdb::math::Mat4d;

namespace {

constexpr double kMaxRangeMapPixels = 6.4e7;
constexpr double kMaxPixelsPerSample = 64.0;
constexpr double kMinPixelLimit = 4096.0;

/// The finer of the range grid's two median sample spacings as seen along
/// the line of sight (`local`: the points in the map frame, z along the line
/// of sight); 0 if the grid has no neighbouring samples.
double finerSampleSpacing(const RangeGridScan& scan, const std::vector<Vec3d>& local) {
  std::vector<double> along[2];
  for (int r = 0; r < scan.rows; ++r)
    for (int c = 0; c < scan.cols; ++c) {
      const int a = scan.grid[static_cast<std::size_t>(r) * scan.cols + c];
      if (a < 0) continue;
      for (int dir = 0; dir < 2; ++dir) {
        const int rr = r + dir, cc = c + 1 - dir;
        if (rr >= scan.rows || cc >= scan.cols) continue;
        const int b = scan.grid[static_cast<std::size_t>(rr) * scan.cols + cc];
        if (b < 0) continue;
        const Vec3d d = local[a] - local[b];
        along[dir].push_back(std::sqrt(d.x() * d.x() + d.y() * d.y()));
      }
    }
  const double m0 = median(std::move(along[0])), m1 = median(std::move(along[1]));
  return std::min(m0 > 0.0 ? m0 : m1, m1 > 0.0 ? m1 : m0);
}

}  // namespace

Mat4d StanfordPlacement::scanToWorld() const {
  // The .conf's quaternion turns the world into the scan: p_world = R^T p + t,
  // the rotation of the conjugate quaternion.
  return rigidMotion(openvdb::math::Quatd(-rotation.x(), -rotation.y(), -rotation.z(), rotation.w()), translation);
}

std::vector<StanfordPlacement> readStanfordConf(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  std::vector<StanfordPlacement> scans;
  forEachTextRecord(path, [&](int line, const std::string& at, std::istringstream& words) {
    std::string key;
    words >> key;
    if (key == "camera" || key == "mesh") return;  // viewer entries, not scans
    if (key != "bmesh") throw InputError(path, at + "unknown entry " + quote(key) + " (expected bmesh, mesh or camera)");
    const char* const expected = "'bmesh FILE tx ty tz qi qj qk qr'";
    StanfordPlacement s;
    s.line = line;
    if (!(words >> s.file)) throw InputError(path, at + "expected " + expected);
    double v[7];
    for (double& x : v) x = nextNumber(words, path, at, expected);
    std::string extra;
    if (words >> extra) throw InputError(path, at + "unexpected " + quote(extra) + " after the quaternion");
    s.translation = Vec3d(v[0], v[1], v[2]);
    s.rotation = unitQuaternion(v[3], v[4], v[5], v[6], path, at);
    s.path = (folder / s.file).string();
    std::error_code ec;  // the non-throwing overload: names may be too long or unreadable
    if (!fs::is_regular_file(s.path, ec))
      throw InputError(path, at + "scan file " + quote(s.file) + " does not exist (looked for " + quote(s.path) + ")");
    scans.push_back(s);
  });
  if (scans.empty()) throw InputError(path, "no 'bmesh' lines: the file places no scans");
  return scans;
}

RangeGridScan readRangeGridPly(const std::string& path, const MemoryBudget& budget) {
  const PlyData ply = readPly(path, budget);
  RangeGridScan scan;
  scan.path = path;
  const PlyElement* vertex = ply.element("vertex");
  if (!vertex) throw InputError(path, "no 'vertex' element");
  const int px = vertex->property("x"), py = vertex->property("y"), pz = vertex->property("z");
  if (px < 0 || py < 0 || pz < 0 || vertex->properties[px].isList || vertex->properties[py].isList ||
      vertex->properties[pz].isList)
    throw InputError(path, "the vertices have no scalar x, y and z");
  scan.points.resize(vertex->count);
  for (std::size_t i = 0; i < vertex->count; ++i) {
    const Vec3d p(vertex->values[px][i], vertex->values[py][i], vertex->values[pz][i]);
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw InputError(path, "vertex " + std::to_string(i) + " has a coordinate that is not finite");
    scan.points[i] = p;
  }

  const PlyElement* grid = ply.element("range_grid");
  if (!grid) throw InputError(path, "no 'range_grid' element: not a range scan");
  const auto readDimension = [&](const char* key) {
    const std::string text = ply.info(key);
    std::size_t used = 0;
    long value = 0;
    try {
      value = std::stol(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (text.empty() || used != text.size() || value <= 0 || value > (1 << 20))
      throw InputError(path, std::string("the header's 'obj_info ") + key + "' is missing or not a positive size");
    return static_cast<int>(value);
  };
  scan.rows = readDimension("num_rows");
  scan.cols = readDimension("num_cols");
  const std::size_t cells = static_cast<std::size_t>(scan.rows) * static_cast<std::size_t>(scan.cols);
  if (grid->count != cells)
    throw InputError(path, "range_grid has " + std::to_string(grid->count) + " entries, but num_rows x num_cols = " +
                               std::to_string(scan.rows) + " x " + std::to_string(scan.cols) + " = " +
                               std::to_string(cells));
  const int list = grid->property("vertex_indices");
  if (list < 0 || !grid->properties[list].isList)
    throw InputError(path, "range_grid has no list property 'vertex_indices'");
  const auto& offsets = grid->listOffsets[list];
  const auto& items = grid->values[list];
  scan.grid.assign(cells, -1);
  std::vector<char> used(scan.points.size(), 0);
  for (std::size_t g = 0; g < cells; ++g) {
    const std::size_t n = offsets[g + 1] - offsets[g];
    if (n == 0) continue;
    const std::string where = "range_grid entry " + std::to_string(g) + " (row " + std::to_string(g / scan.cols) +
                              ", column " + std::to_string(g % scan.cols) + ")";
    if (n != 1) throw InputError(path, where + " lists " + std::to_string(n) + " vertices; at most 1 is allowed");
    const double index = items[offsets[g]];
    if (!(index >= 0.0) || index >= static_cast<double>(scan.points.size()))
      throw InputError(path, where + " points at vertex " + std::to_string(static_cast<long long>(index)) +
                                 ", but there are " + std::to_string(scan.points.size()));
    scan.grid[g] = static_cast<int>(index);
  }
  return scan;
}

std::vector<openvdb::Vec3I> triangulateRangeGrid(const RangeGridScan& scan, double maxEdge) {
  std::vector<openvdb::Vec3I> triangles;
  const auto at = [&](int r, int c) { return scan.grid[static_cast<std::size_t>(r) * scan.cols + c]; };
  const auto shortEdges = [&](int a, int b, int c) {
    const Vec3d& pa = scan.points[a];
    const Vec3d& pb = scan.points[b];
    const Vec3d& pc = scan.points[c];
    return (pa - pb).length() <= maxEdge && (pb - pc).length() <= maxEdge && (pc - pa).length() <= maxEdge;
  };
  for (int r = 0; r + 1 < scan.rows; ++r)
    for (int c = 0; c + 1 < scan.cols; ++c) {
      const int a = at(r, c), b = at(r, c + 1), d = at(r + 1, c), e = at(r + 1, c + 1);
      const int valid = (a >= 0) + (b >= 0) + (d >= 0) + (e >= 0);
      if (valid < 3) continue;
      if (valid == 4) {
        if (shortEdges(a, b, d)) triangles.emplace_back(a, b, d);
        if (shortEdges(b, e, d)) triangles.emplace_back(b, e, d);
        continue;
      }
      int corner[3], n = 0;
      for (int v : {a, b, e, d})
        if (v >= 0) corner[n++] = v;
      if (shortEdges(corner[0], corner[1], corner[2])) triangles.emplace_back(corner[0], corner[1], corner[2]);
    }
  return triangles;
}

double rangeGridSpacing(const RangeGridScan& scan) {
  std::vector<double> d;
  for (int r = 0; r < scan.rows; ++r)
    for (int c = 0; c < scan.cols; ++c) {
      const int a = scan.grid[static_cast<std::size_t>(r) * scan.cols + c];
      if (a < 0) continue;
      if (c + 1 < scan.cols) {
        const int b = scan.grid[static_cast<std::size_t>(r) * scan.cols + c + 1];
        if (b >= 0) d.push_back((scan.points[a] - scan.points[b]).length());
      }
      if (r + 1 < scan.rows) {
        const int b = scan.grid[static_cast<std::size_t>(r + 1) * scan.cols + c];
        if (b >= 0) d.push_back((scan.points[a] - scan.points[b]).length());
      }
    }
  return median(std::move(d));
}

RangeMap rangeMapFromScan(const RangeGridScan& scan, const Mat4d& scanToWorld, const StanfordScanOptions& options,
                          const std::string& name) {
  const double spacing = rangeGridSpacing(scan);
  if (!(spacing > 0.0)) throw InputError(scan.path, "the range grid has no neighbouring samples: nothing to triangulate");
  const std::vector<openvdb::Vec3I> triangles = triangulateRangeGrid(scan, options.maxEdgeFactor * spacing);
  if (triangles.empty()) throw InputError(scan.path, "no triangles between the range grid's samples");

  // The map frame: +z along the line of sight, away from the scanner.
  const double tl = options.towardScanner.length();
  if (!(tl > 0.0) || !std::isfinite(tl)) throw InputError(scan.path, "the direction toward the scanner is zero");
  if (!(options.edgeExtension >= 0.0) || !(options.edgeExtension <= 8.0))
    throw InputError(scan.path, "the edge extension must be 0 to 8 pixels");
  const FrameAlong axes(-options.towardScanner);

  std::vector<Vec3d> local(scan.points.size());
  double xmin = std::numeric_limits<double>::max(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (std::size_t i = 0; i < scan.points.size(); ++i) {
    const Vec3d& p = scan.points[i];
    local[i] = axes.local(p);
    xmin = std::min(xmin, local[i].x());
    xmax = std::max(xmax, local[i].x());
    ymin = std::min(ymin, local[i].y());
    ymax = std::max(ymax, local[i].y());
  }
  // Two pixels per sample along the finer of the grid's two directions, as
  // seen along the line of sight: no reading is lost to the raster, and the
  // bilinear interpolation of the map follows the triangles between samples.
  const double finer = finerSampleSpacing(scan, local);
  const double raySpacing = finer > 0.0 ? finer : spacing;
  const double pixel = options.pixelSize > 0.0 ? options.pixelSize : 0.5 * raySpacing;
  // A border around the samples, wide enough for the edge extension.
  const int border = 1 + static_cast<int>(std::ceil(options.edgeExtension));
  const double cols = std::ceil((xmax - xmin) / pixel) + 1 + 2 * border;
  const double rows = std::ceil((ymax - ymin) / pixel) + 1 + 2 * border;
  // A map with far more pixels than the grid has samples is nearly empty (a
  // stray point far away, a pixel far finer than the samples): refused before
  // it is allocated, as is one too large for memory.
  const double gridSamples = static_cast<double>(scan.rows) * static_cast<double>(scan.cols);
  const double maxPixels = std::min(kMaxRangeMapPixels, std::max(kMinPixelLimit, kMaxPixelsPerSample * gridSamples));
  if (!(cols * rows <= maxPixels)) {  // also when the extent overflowed to infinity or NaN
    char problem[200];
    std::snprintf(problem, sizeof(problem),
                  "the scan would need a range map of %.12g x %.12g pixels of %g m, more than the %.12g its %d x %d "
                  "grid allows: choose a larger pixel size",
                  cols, rows, pixel, maxPixels, scan.rows, scan.cols);
    throw InputError(scan.path, problem);
  }
  const int width = static_cast<int>(cols), height = static_cast<int>(rows);
  OrthographicProjection projection{pixel, openvdb::math::Vec2d(xmin - border * pixel, ymin - border * pixel)};

  // Rasterise the triangles along the line of sight, and just beyond the
  // scan's boundary so that its boundary samples are not lost.
  std::vector<Vec3d> pixels(local.size());
  for (std::size_t i = 0; i < local.size(); ++i)
    pixels[i] = Vec3d((local[i].x() - projection.origin.x()) / pixel, (local[i].y() - projection.origin.y()) / pixel,
                      local[i].z());
  std::vector<float> depth = rasteriseDepth(pixels, triangles, width, height, options.edgeExtension);
  const Mat4d mapToScan(axes.x.x(), axes.x.y(), axes.x.z(), 0.0, axes.y.x(), axes.y.y(), axes.y.z(), 0.0, axes.z.x(),
                        axes.z.y(), axes.z.z(), 0.0, 0.0, 0.0, 0.0, 1.0);
  double sigma = options.sigma;
  if (!(sigma > 0.0)) {
    sigma = estimateRangeNoise(scan, options.towardScanner);
    sigma = sigma > 0.0 ? std::max(sigma, 0.01 * raySpacing) : 0.25 * raySpacing;
  }
  RangeMap map = RangeMap::orthographic(width, height, std::move(depth), projection, mapToScan * scanToWorld, sigma,
                                       name);
  std::vector<Vec3d> samples(scan.points.size());
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = scanToWorld.transform(scan.points[i]);
  map.setSamples(std::move(samples), raySpacing);
  return map;
}

std::vector<RangeMap> loadStanfordScans(const std::string& confPath, const StanfordScanOptions& options) {
  std::vector<RangeMap> maps;
  const std::vector<StanfordPlacement> placements = readStanfordConf(confPath);
  for (std::size_t i = 0; i < placements.size(); ++i) {
    checkInterrupter(options.interrupter);
    const StanfordPlacement& s = placements[i];
    if (!options.wanted || options.wanted(i))
      maps.push_back(rangeMapFromScan(readRangeGridPly(s.path, options.memoryBudget), s.scanToWorld(), options, s.file));
    reportLoaded(options.progress, i + 1, placements.size());
  }
  return maps;
}

}  // namespace levelfuse::io

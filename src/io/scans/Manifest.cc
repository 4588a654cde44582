// levelfuse: JSON scan manifests.

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/io/scans/TumScans.h>

#include "ManifestEntry.h"
#include "ManifestPointEntries.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <utility>

namespace levelfuse::io {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Manifests list scans; a larger file is not one.
constexpr std::uintmax_t kMaxManifestBytes = 64 << 20;

StanfordScanOptions stanfordOptions(const Entry& e) {
  StanfordScanOptions o;
  if (e.has("toward_scanner")) {
    const auto v = e.numbers("toward_scanner", 3);
    o.towardScanner = openvdb::Vec3d(v[0], v[1], v[2]);
    if (o.towardScanner.length() == 0.0) e.fail("'toward_scanner' is the zero vector");
  }
  // Without a sigma, each scan's noise is estimated from the scan itself.
  if (e.has("sigma")) o.sigma = e.positive("sigma", 0.0);
  o.pixelSize = e.number("pixel_size", 0.0);
  if (o.pixelSize < 0.0) e.fail("'pixel_size' must not be negative");
  return o;
}

PinholeProjection intrinsicsOf(const Entry& e) {
  if (e.has("intrinsics_file")) return readIntrinsics(e.path("intrinsics_file"));
  if (!e.has("intrinsics")) e.fail("missing 'intrinsics' or 'intrinsics_file'");
  const json& k = e["intrinsics"];
  PinholeProjection p;
  for (const auto& [key, target] : {std::pair<const char*, double*>{"fx", &p.fx}, {"fy", &p.fy}, {"cx", &p.cx}, {"cy", &p.cy}}) {
    if (!k.contains(key)) e.fail(std::string("'intrinsics' needs a number '") + key + "'");
    *target = e.numberIn(k[key], std::string("'intrinsics.") + key + "'");
  }
  if (!(p.fx > 0.0) || !(p.fy > 0.0)) e.fail("the focal lengths must be positive");
  return p;
}

DepthNoise depthNoiseOf(const Entry& e) {
  DepthNoise noise;
  if (!e.has("sigma")) return noise;
  const json& s = e["sigma"];
  if (s.is_number()) {
    noise.minimum = e.numberIn(s, "'sigma'");
    noise.perSquareMetre = 0.0;
  } else if (s.is_object()) {
    if (s.contains("minimum")) noise.minimum = e.numberIn(s["minimum"], "'sigma.minimum'");
    if (s.contains("per_square_metre"))
      noise.perSquareMetre = e.numberIn(s["per_square_metre"], "'sigma.per_square_metre'");
    if (s.contains("per_metre")) noise.perMetre = e.numberIn(s["per_metre"], "'sigma.per_metre'");
  } else {
    e.fail("'sigma' must be a number or {\"minimum\", \"per_metre\", \"per_square_metre\"}");
  }
  if (!(noise.minimum > 0.0) || noise.perSquareMetre < 0.0 || noise.perMetre < 0.0) e.fail("'sigma' must be positive");
  return noise;
}

/// A TUM RGB-D folder's entry: the folder, and optionally its depth scale,
/// maximum depth, frame stride and noise.
std::vector<RangeMap> loadTumEntry(const Entry& e, const ScanLoadOptions& defaults) {
  ScanLoadOptions o = defaults;
  o.progress = {};  // a manifest reports its entries, not the frames within one
  // The manifest hands its scans over, in the order of its entries, and asks which are wanted.
  o.take = {};
  o.wanted = {};
  if (e.has("depth_scale")) o.depthScale = e.positive("depth_scale", 0.0);
  o.maxDepth = e.positive("max_depth", defaults.maxDepth);
  const double stride = e.number("frame_stride", 1.0);
  if (stride < 1.0 || stride > 1e6 || stride != std::floor(stride))
    e.fail("'frame_stride' must be a whole number, 1 to 1000000");
  o.frameStride = static_cast<int>(stride);
  o.depthNoise = depthNoiseOf(e);
  const std::string folder = e.folder("folder");
  if (!isTumFolder(folder)) e.fail("'folder': " + folder + " holds no depth.txt: not a TUM RGB-D folder");
  return loadTumFolder(folder, o);
}

/// A spherical scan's angular grid of `rows` rows, in degrees:
/// "azimuth_start", "azimuth_step", and either "elevation_start" and
/// "elevation_step" or "row_elevations", one per row (uneven rows).
SphericalProjection sphericalGridOf(const Entry& e, int rows) {
  constexpr double kRadians = M_PI / 180.0;
  SphericalProjection grid;
  const bool unevenRows = e.has("row_elevations");
  if (unevenRows && e.countOf({"elevation_start", "elevation_step"}) > 0)
    e.fail("give 'row_elevations' or 'elevation_start' and 'elevation_step', not both");
  std::vector<std::pair<const char*, double*>> keys{{"azimuth_start", &grid.azimuthStart},
                                                    {"azimuth_step", &grid.azimuthStep}};
  if (!unevenRows) keys.insert(keys.end(), {{"elevation_start", &grid.elevationStart}, {"elevation_step", &grid.elevationStep}});
  for (const auto& [key, target] : keys) {
    if (!e.has(key)) e.fail(std::string("missing '") + key + "' (degrees)");
    *target = e.number(key, 0.0) * kRadians;
  }
  if (unevenRows) {
    grid.rowElevations = e.numbers("row_elevations", static_cast<std::size_t>(rows));
    for (double& elevation : grid.rowElevations) elevation *= kRadians;
  }
  return grid;
}

/// A station file's options (PTX, E57): the manifest's, with the entry's own
/// noise of its readings if it gives one. Its scans are collected with the
/// manifest's others, not handed over one at a time, so that the entry's own
/// options apply to them.
ScanLoadOptions stationEntryOptions(const Entry& e, const ScanLoadOptions& defaults) {
  ScanLoadOptions o;
  o.interrupter = defaults.interrupter;
  o.memoryBudget = defaults.memoryBudget;
  o.stationSigma = e.positive("sigma", defaults.stationSigma);
  return o;
}

json parseManifest(const std::string& path) {
  requireInputFile(path);
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (!ec && bytes > kMaxManifestBytes)
    throw InputError(path, "a manifest of " + std::to_string(bytes >> 20) +
                               " MiB: manifests list scans and take a few KiB; is this the right file?");
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be opened for reading");
  try {
    return json::parse(in);
  } catch (const json::exception& e) {  // parse errors, and numbers too large for a double
    throw InputError(path, "not valid JSON (" + excerpt(e.what()) + ")");
  }
}

/// An entry's "colour": a PNG registered pixel for pixel to the one range map
/// the entry holds (maps[first]).
void colourEntry(const Entry& e, std::vector<RangeMap>& maps, std::size_t first, const MemoryBudget& budget) {
  if (maps.size() != first + 1)
    e.fail("'colour' is a colour image registered to one range map; this entry holds " +
           std::to_string(maps.size() - first));
  const std::string file = e.path("colour");
  colourRangeMap(maps[first], readColourPng(file, budget), file);
}

}  // namespace

namespace {

/// Whether an entry of `format` makes one scan: one not wanted (ScanLoadOptions::wanted) is not read.
bool makesOneScan(const std::string& format) {
  for (const char* one : {"stanford-ply", "depth-png", "depth-pfm", "depth-exr", "points", "kitti-bin",
                          "orthographic-pfm", "spherical-pfm"})
    if (format == one) return true;
  return false;
}

/// Of the scans from `first` on, keeps those `wanted` picks, asking it of each in
/// order with the number of scans asked before (`asked`, counted on).
void keepWanted(std::vector<RangeMap>& maps, std::size_t first, const std::function<bool(std::size_t)>& wanted,
                std::size_t& asked) {
  std::size_t kept = first;
  for (std::size_t m = first; m < maps.size(); ++m)
    if (wanted(asked++)) maps[kept++] = std::move(maps[m]);
  maps.erase(maps.begin() + static_cast<std::ptrdiff_t>(kept), maps.end());
}

/// A "stanford-conf" entry's scans: a Stanford .conf file's.
std::vector<RangeMap> loadStanfordConfEntry(const Entry& e, const ScanLoadOptions& defaults) {
  StanfordScanOptions stanford = stanfordOptions(e);
  stanford.interrupter = defaults.interrupter;
  stanford.memoryBudget = defaults.memoryBudget;
  return loadStanfordScans(e.path("file"), stanford);
}

/// A "stanford-ply" entry's scan: a range grid placed by a translation and a unit quaternion.
RangeMap loadStanfordPlyEntry(const Entry& e, const MemoryBudget& budget) {
  StanfordPlacement placement;
  const auto t = e.numbers("translation", 3);
  const auto q = e.numbers("quaternion", 4);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm < 1e-9 || std::fabs(norm - 1.0) > 1e-3)
    e.fail("'quaternion' has norm " + std::to_string(norm) + ": a rotation needs a unit quaternion");
  placement.translation = openvdb::Vec3d(t[0], t[1], t[2]);
  placement.rotation = openvdb::math::Quatd(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
  const std::string file = e.path("file");
  return rangeMapFromScan(readRangeGridPly(file, budget), placement.scanToWorld(), stanfordOptions(e),
                          fs::path(file).filename().string());
}

/// A depth image's entry ("depth-png", "depth-pfm" or "depth-exr"): the
/// image, its intrinsics and pose, and optionally its scale, maximum depth
/// and noise (`path`: the manifest's).
RangeMap loadDepthImageEntry(const Entry& e, const std::string& format, const std::string& path,
                             const ScanLoadOptions& defaults) {
  const std::string file = e.path("file");
  const double defaultScale = defaults.depthScale > 0.0 ? defaults.depthScale : 0.001;
  const MemoryBudget& budget = defaults.memoryBudget;
  DepthImage image = format == "depth-png"
                         ? readDepthPng(file, e.positive("depth_scale", defaultScale), {0u, 65535u}, budget)
                     : format == "depth-pfm" ? readDepthPfm(file, true, budget)
                                             : readDepthExr(file, budget);
  dropReadingsBeyond(image, e.positive("max_depth", defaults.maxDepth));
  const PinholeProjection intrinsics = intrinsicsOf(e);
  const openvdb::math::Mat4d pose = poseOf(e, path);
  return e.checked([&] {
    return depthFrame(std::move(image), intrinsics, pose, depthNoiseOf(e), fs::path(file).filename().string());
  });
}

/// An "orthographic-pfm" entry's scan: depths along parallel rays, their
/// pixel size, origin, pose and noise (`path`: the manifest's).
RangeMap loadOrthographicEntry(const Entry& e, const std::string& path, const MemoryBudget& budget) {
  const std::string file = e.path("file");
  DepthImage image = readDepthPfm(file, false, budget);
  if (!e.has("pixel_size")) e.fail("missing 'pixel_size'");
  OrthographicProjection projection;
  projection.pixelSize = e.positive("pixel_size", 0.0);
  if (e.has("origin")) {
    const auto o = e.numbers("origin", 2);
    projection.origin = openvdb::math::Vec2d(o[0], o[1]);
  }
  if (!e.has("sigma")) e.fail("missing 'sigma'");
  const double sigma = e.positive("sigma", 0.0);
  return e.checked([&] {
    return RangeMap::orthographic(image.width, image.height, std::move(image.depth), projection, poseOf(e, path),
                                  sigma, fs::path(file).filename().string());
  });
}

/// A "spherical-pfm" entry's scan: ranges on an angular grid, its pose and
/// noise (`path`: the manifest's).
RangeMap loadSphericalEntry(const Entry& e, const std::string& path, const MemoryBudget& budget) {
  const std::string file = e.path("file");
  DepthImage image = readDepthPfm(file, true, budget);
  if (!e.has("sigma")) e.fail("missing 'sigma'");
  const SphericalProjection grid = sphericalGridOf(e, image.height);
  return e.checked([&] {
    return RangeMap::spherical(image.width, image.height, std::move(image.depth), grid, poseOf(e, path),
                               depthNoiseOf(e), fs::path(file).filename().string());
  });
}

/// Appends the scans of entry `e`, of format `format`, to `maps` (`path`: the manifest's).
void appendEntryScans(const Entry& e, const std::string& format, const std::string& path,
                      const ScanLoadOptions& defaults, std::vector<RangeMap>& maps) {
  const auto append = [&](std::vector<RangeMap> loaded) {
    for (RangeMap& m : loaded) maps.push_back(std::move(m));
  };
  if (format == "stanford-conf") append(loadStanfordConfEntry(e, defaults));
  else if (format == "stanford-ply") maps.push_back(loadStanfordPlyEntry(e, defaults.memoryBudget));
  else if (format == "depth-png" || format == "depth-pfm" || format == "depth-exr")
    maps.push_back(loadDepthImageEntry(e, format, path, defaults));
  else if (format == "tum") append(loadTumEntry(e, defaults));
  else if (format == "ptx") append(loadPtxScans(e.path("file"), stationEntryOptions(e, defaults)));
  else if (format == "e57") append(loadE57Scans(e.path("file"), stationEntryOptions(e, defaults)));
  else if (format == "points") maps.push_back(loadPointsEntry(e, defaults));
  else if (format == "kitti-bin") append(loadKittiBinEntry(e, defaults));
  else if (format == "orthographic-pfm") maps.push_back(loadOrthographicEntry(e, path, defaults.memoryBudget));
  else if (format == "spherical-pfm") maps.push_back(loadSphericalEntry(e, path, defaults.memoryBudget));
  else
    e.fail("unknown format " + quote(format) +
           " (stanford-conf, stanford-ply, depth-png, depth-pfm, depth-exr, tum, ptx, e57, points, kitti-bin, "
           "orthographic-pfm or spherical-pfm)");
}

/// An entry's "misses_are_empty" and "dropout_reach", for the scans it holds (maps[first] on).
void setMissesAreEmpty(const Entry& e, std::vector<RangeMap>& maps, std::size_t first) {
  if (!e["misses_are_empty"].is_boolean()) e.fail("'misses_are_empty' must be true or false");
  const double reach = e.number("dropout_reach", 2.0);
  if (reach < 0.0 || reach > 1000.0 || reach != std::floor(reach))
    e.fail("'dropout_reach' must be a whole number of pixels, 0 to 1000");
  for (std::size_t m = first; m < maps.size(); ++m)
    maps[m].setMissesAreEmpty(e["misses_are_empty"].get<bool>(), static_cast<int>(reach));
}

}  // namespace

std::vector<RangeMap> loadManifest(const std::string& path, const ScanLoadOptions& defaults) {
  const json root = parseManifest(path);
  if (!root.is_object() || !root.contains("scans") || !root["scans"].is_array())
    throw InputError(path, "expected an object with an array 'scans'");
  if (root["scans"].empty()) throw InputError(path, "'scans' is empty");

  std::vector<RangeMap> maps;
  std::size_t asked = 0;  // scans the options' wanted was asked of
  for (std::size_t i = 0; i < root["scans"].size(); ++i) {
    checkInterrupter(defaults.interrupter);
    const Entry e(path, root["scans"][i], i);
    const std::string format = e.string("format");
    if (defaults.wanted && makesOneScan(format) && !defaults.wanted(asked++)) {
      reportLoaded(defaults.progress, i + 1, root["scans"].size());
      continue;
    }
    const std::size_t first = maps.size();
    appendEntryScans(e, format, path, defaults, maps);
    if (e.has("colour")) colourEntry(e, maps, first, defaults.memoryBudget);
    if (e.has("misses_are_empty")) setMissesAreEmpty(e, maps, first);
    if (defaults.wanted && !makesOneScan(format)) keepWanted(maps, first, defaults.wanted, asked);
    reportLoaded(defaults.progress, i + 1, root["scans"].size());
  }
  return maps;
}

std::optional<shapes::AnalyticShape> loadManifestTruth(const std::string& path) {
  const json root = parseManifest(path);
  if (!root.contains("truth")) return std::nullopt;
  const json& t = root["truth"];
  const auto fail = [&](const std::string& problem) -> void { throw InputError(path, "truth: " + problem); };
  if (!t.is_object() || !t.contains("shape") || !t["shape"].is_string()) fail("expected an object with a 'shape'");
  const auto number = [&](const char* key) {
    if (!t.contains(key) || !t[key].is_number() || !std::isfinite(t[key].get<double>()))
      fail(std::string("'") + key + "' must be a number");
    return t[key].get<double>();
  };
  openvdb::Vec3d centre(0.0);
  if (t.contains("centre")) {
    if (!t["centre"].is_array() || t["centre"].size() != 3) fail("'centre' needs 3 numbers");
    for (int i = 0; i < 3; ++i) {
      if (!t["centre"][i].is_number()) fail("'centre' needs 3 numbers");
      centre[i] = t["centre"][i].get<double>();
    }
  }
  shapes::AnalyticShape truth;
  const std::string shape = t["shape"].get<std::string>();
  if (shape == "sphere") {
    truth.kind = shapes::AnalyticShape::Kind::kSphere;
    truth.sphere = shapes::Sphere{centre, number("radius")};
  } else if (shape == "torus") {
    truth.kind = shapes::AnalyticShape::Kind::kTorus;
    truth.torus = shapes::Torus{centre, number("major"), number("minor")};
  } else if (shape == "mug") {
    truth.kind = shapes::AnalyticShape::Kind::kMug;
    truth.mug = shapes::Mug{centre,          number("radius"),      number("height"),
                            number("wall"), number("handle_bend"), number("handle_radius")};
  } else if (shape == "room") {
    truth.kind = shapes::AnalyticShape::Kind::kRoom;
    truth.room = shapes::Room{centre, openvdb::Vec3d(number("width"), number("depth"), number("height"))};
    if (!(truth.room.size.x() > 0.0 && truth.room.size.y() > 0.0 && truth.room.size.z() > 0.0))
      fail("a room's width, depth and height must be positive");
  } else {
    fail("unknown shape " + quote(shape) + " (sphere, torus, mug or room)");
  }
  return truth;
}

std::string writeScanSet(const std::string& directory, const std::vector<RangeMap>& maps,
                         const std::optional<shapes::AnalyticShape>& truth) {
  OutputSet outputs;
  const std::string manifest = writeScanSet(outputs, directory, maps, truth);
  outputs.commit();
  return manifest;
}

namespace {

/// A matrix's entries row after row, as manifests write poses (OpenVDB's row vectors: the transpose).
std::vector<double> rowMajor(const openvdb::math::Mat4d& m) {
  std::vector<double> v(16);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v[static_cast<std::size_t>(4 * r + c)] = m(c, r);
  return v;
}

/// A manifest entry's projection: its format and the keys of its pixel grid.
void writeProjection(const RangeMap& m, json& entry) {
  if (m.kind() == RangeMap::Kind::kOrthographic) {
    entry["format"] = "orthographic-pfm";
    entry["pixel_size"] = m.orthographicProjection().pixelSize;
    entry["origin"] = {m.orthographicProjection().origin.x(), m.orthographicProjection().origin.y()};
  } else if (m.kind() == RangeMap::Kind::kSpherical) {
    constexpr double kDegrees = 180.0 / M_PI;
    const SphericalProjection& p = m.sphericalProjection();
    entry["format"] = "spherical-pfm";
    entry["azimuth_start"] = p.azimuthStart * kDegrees;
    entry["azimuth_step"] = p.azimuthStep * kDegrees;
    if (p.rowElevations.empty()) {
      entry["elevation_start"] = p.elevationStart * kDegrees;
      entry["elevation_step"] = p.elevationStep * kDegrees;
    } else {
      std::vector<double> rows;
      for (const double elevation : p.rowElevations) rows.push_back(elevation * kDegrees);
      entry["row_elevations"] = rows;
    }
  } else {
    const PinholeProjection& p = m.pinholeProjection();
    entry["format"] = "depth-pfm";
    entry["intrinsics"] = {{"fx", p.fx}, {"fy", p.fy}, {"cx", p.cx}, {"cy", p.cy}};
  }
}

/// Writes range map `m`, the j-th, into `directory` (its readings as
/// scan<j>.pfm, its colours as scan<j>.colour.png) and returns its manifest entry.
json writeScan(OutputSet& outputs, const std::string& directory, const RangeMap& m, std::size_t j) {
  if (m.hasRayDirections()) throw std::invalid_argument("writeScanSet: per-pixel rays cannot be written");
  const std::string file = "scan" + std::to_string(j) + ".pfm";
  DepthImage image;
  image.width = m.width();
  image.height = m.height();
  image.depth.reserve(static_cast<std::size_t>(m.width()) * m.height());
  for (int v = 0; v < m.height(); ++v)
    for (int u = 0; u < m.width(); ++u) image.depth.push_back(m.reading(u, v));
  writeDepthPfm(outputs, (fs::path(directory) / file).string(), image);
  json entry{{"file", file}, {"pose", rowMajor(m.mapToWorld())}, {"sigma", m.sigma()}};
  if (m.hasColours()) {
    const std::string colourFile = "scan" + std::to_string(j) + ".colour.png";
    writeColourPng(outputs, (fs::path(directory) / colourFile).string(), colourImageOf(m));
    entry["colour"] = colourFile;
  }
  if (const DepthNoise* noise = m.depthNoise())
    entry["sigma"] = {
        {"minimum", noise->minimum}, {"per_metre", noise->perMetre}, {"per_square_metre", noise->perSquareMetre}};
  writeProjection(m, entry);
  if (m.missesAreEmpty()) {
    entry["misses_are_empty"] = true;
    entry["dropout_reach"] = m.dropoutReach();
  }
  return entry;
}

/// A manifest's "truth": the analytic shape the scans were made of.
json truthEntry(const shapes::AnalyticShape& truth) {
  const auto vec = [](const openvdb::Vec3d& v) { return json::array({v.x(), v.y(), v.z()}); };
  switch (truth.kind) {
    case shapes::AnalyticShape::Kind::kSphere:
      return {{"shape", "sphere"}, {"centre", vec(truth.sphere.centre)}, {"radius", truth.sphere.radius}};
    case shapes::AnalyticShape::Kind::kTorus:
      return {{"shape", "torus"}, {"centre", vec(truth.torus.centre)}, {"major", truth.torus.major},
              {"minor", truth.torus.minor}};
    case shapes::AnalyticShape::Kind::kMug:
      return {{"shape", "mug"},          {"centre", vec(truth.mug.centre)},
              {"radius", truth.mug.radius}, {"height", truth.mug.height},
              {"wall", truth.mug.wall},     {"handle_bend", truth.mug.handleBend},
              {"handle_radius", truth.mug.handleRadius}};
    case shapes::AnalyticShape::Kind::kRoom:
      return {{"shape", "room"},
              {"centre", vec(truth.room.centre)},
              {"width", truth.room.size.x()},
              {"depth", truth.room.size.y()},
              {"height", truth.room.size.z()}};
  }
  return nullptr;
}

}  // namespace

std::string writeScanSet(OutputSet& outputs, const std::string& directory, const std::vector<RangeMap>& maps,
                         const std::optional<shapes::AnalyticShape>& truth) {
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw std::runtime_error("cannot create the folder '" + directory + "': " + ec.message());
  json scans = json::array();
  for (std::size_t j = 0; j < maps.size(); ++j) scans.push_back(writeScan(outputs, directory, maps[j], j));
  json root{{"scans", scans}};
  if (truth) {
    const json shape = truthEntry(*truth);
    if (!shape.is_null()) root["truth"] = shape;
  }
  const std::string manifest = (fs::path(directory) / "scans.json").string();
  outputs.add(manifest, [&](const std::string& temporary) {
    std::ofstream out(temporary);
    if (!out) throw std::runtime_error("cannot open a temporary file beside it");
    out << root.dump(2) << "\n";
    closeChecked(out);
  });
  return manifest;
}

}  // namespace levelfuse::io

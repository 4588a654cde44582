// levelfuse info: what is in a .vdb file or a set of scans.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/RequireLevelSet.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace levelfuse::cli {
namespace {

struct InfoSettings {
  std::vector<std::string> paths;
  std::string towardScanner;
  bool json = false;
};

nlohmann::json describeVdb(const std::string& path) {
  openvdb::MetaMap::Ptr fileMeta;
  const openvdb::GridPtrVecPtr grids = io::readVdb(path, &fileMeta);
  nlohmann::json list = nlohmann::json::array();
  for (const openvdb::GridBase::Ptr& base : *grids) {
    nlohmann::json g{{"name", base->getName()},
                     {"type", base->valueType()},
                     {"class", openvdb::GridBase::gridClassToString(base->getGridClass())},
                     {"voxel_size", base->voxelSize()[0]},
                     {"active_voxels", base->activeVoxelCount()},
                     {"memory_bytes", base->memUsage()}};
    const openvdb::CoordBBox box = base->evalActiveVoxelBoundingBox();
    if (!box.empty()) {
      const openvdb::Vec3d lo = base->indexToWorld(box.min()), hi = base->indexToWorld(box.max());
      g["bounds"] = {{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}};
    }
    if (const auto grid = openvdb::GridBase::grid<openvdb::FloatGrid>(base);
        grid && grid->getGridClass() == openvdb::GRID_LEVEL_SET) {
      g["background"] = grid->background();
      const std::string problem = levelSetProblem(*grid);
      if (problem.empty()) g["inside_components"] = insideComponents(*grid);
      else g["problem"] = problem;
    }
    nlohmann::json meta = nlohmann::json::object();
    for (auto it = base->beginMeta(); it != base->endMeta(); ++it)
      if (it->first.rfind("levelfuse_", 0) == 0) meta[it->first] = it->second->str();
    if (!meta.empty()) g["levelfuse"] = meta;
    list.push_back(g);
  }
  return {{"path", path}, {"kind", "vdb"}, {"grids", list}};
}

/// A spherical map's angular grid in degrees: its azimuth step, and its
/// elevation step or, for uneven rows, their elevations.
nlohmann::json angularGrid(const RangeMap& m) {
  constexpr double kDegrees = 180.0 / M_PI;
  const SphericalProjection& p = m.sphericalProjection();
  nlohmann::json grid{{"azimuth_step", std::fabs(p.azimuthStep) * kDegrees}};
  if (p.rowElevations.empty()) {
    grid["elevation_step"] = std::fabs(p.elevationStep) * kDegrees;
    return grid;
  }
  std::vector<double> rows;
  for (const double elevation : p.rowElevations) rows.push_back(elevation * kDegrees);
  grid["row_elevations"] = rows;
  return grid;
}

/// "steps 0.17 x 0.3333 deg", or for uneven rows "steps 0.17 deg x 64 rows
/// 0.3333 to 0.5 deg apart".
std::string angularGridText(const nlohmann::json& grid) {
  const std::string azimuth = fixed(grid["azimuth_step"].get<double>());
  if (grid.contains("elevation_step"))
    return "steps " + azimuth + " x " + fixed(grid["elevation_step"].get<double>()) + " deg";
  const std::vector<double> rows = grid["row_elevations"].get<std::vector<double>>();
  double closest = rows[1] - rows[0], widest = closest;
  for (std::size_t r = 2; r < rows.size(); ++r) {
    closest = std::min(closest, rows[r] - rows[r - 1]);
    widest = std::max(widest, rows[r] - rows[r - 1]);
  }
  return "steps " + azimuth + " deg x " + std::to_string(rows.size()) + " rows " + fixed(closest) + " to " +
         fixed(widest) + " deg apart";
}

nlohmann::json describeScans(const std::string& path, const InfoSettings& s) {
  io::ScanLoadOptions load;
  if (!s.towardScanner.empty()) load.stanford.towardScanner = parseVec3(s.towardScanner);
  const std::vector<RangeMap> maps = io::loadScans(path, load);
  nlohmann::json list = nlohmann::json::array();
  openvdb::BBoxd all;
  std::size_t readings = 0, points = 0;
  for (const RangeMap& m : maps) {
    all.expand(m.readingBounds());
    readings += m.validCount();
    points += m.sampleCount();
    const openvdb::Vec3d scanner = m.raysFromOneCentre() ? m.scannerPosition()
                                                         : -m.mapToWorld().transform3x3(openvdb::Vec3d(0, 0, 1));
    const char* scannerKey = m.kind() == RangeMap::Kind::kPinhole     ? "camera_position"
                             : m.kind() == RangeMap::Kind::kSpherical ? "scanner_position"
                                                                      : "toward_scanner";
    list.push_back({{"name", m.name()},
                    {"projection", projectionName(m.kind())},
                    {"width", m.width()},
                    {"height", m.height()},
                    {"points", m.sampleCount()},
                    {"readings", m.validCount()},
                    {"ray_spacing", m.typicalRaySpacing()},
                    {"sigma", m.sigma()},
                    {"coloured", m.hasColours()},
                    {scannerKey, {scanner.x(), scanner.y(), scanner.z()}}});
    if (m.kind() == RangeMap::Kind::kSpherical) list.back()["angular_grid"] = angularGrid(m);
  }
  nlohmann::json j{{"path", path},
                   {"kind", "scans"},
                   {"scans", list},
                   {"points", points},
                   {"readings", readings},
                   {"bounds", {{all.min().x(), all.min().y(), all.min().z()}, {all.max().x(), all.max().y(), all.max().z()}}}};
  if (std::filesystem::path(path).extension() == ".json")
    if (const auto truth = io::loadManifestTruth(path)) j["truth"] = truth->name();
  return j;
}

/// "(x, y, z)" with six significant digits, for people.
std::string point(const nlohmann::json& xyz) {
  return "(" + fixed(xyz[0].get<double>(), 6) + ", " + fixed(xyz[1].get<double>(), 6) + ", " +
         fixed(xyz[2].get<double>(), 6) + ")";
}

void print(const nlohmann::json& j) {
  const std::string path = j["path"];
  if (j["kind"] == "vdb") {
    std::cout << path << ": OpenVDB file, " << j["grids"].size() << (j["grids"].size() == 1 ? " grid\n" : " grids\n");
    for (const auto& g : j["grids"]) {
      std::cout << "  '" << g["name"].get<std::string>() << "': " << g["type"].get<std::string>() << " "
                << g["class"].get<std::string>() << ", voxel " << length(g["voxel_size"].get<double>()) << ", "
                << withCommas(g["active_voxels"].get<std::size_t>()) << " active voxels, "
                << mebibytes(g["memory_bytes"].get<std::size_t>()) << "\n";
      if (g.contains("bounds"))
        std::cout << "    bounds " << point(g["bounds"][0]) << " to " << point(g["bounds"][1]) << " m\n";
      if (g.contains("inside_components"))
        std::cout << "    level set: background " << length(g["background"].get<double>()) << ", "
                  << g["inside_components"].get<int>() << " inside component(s)\n";
      if (g.contains("problem")) std::cout << "    not usable as a level set: " << g["problem"].get<std::string>() << "\n";
      if (g.contains("levelfuse"))
        for (const auto& [key, value] : g["levelfuse"].items())
          std::cout << "    " << key << " = " << value.get<std::string>() << "\n";
    }
    return;
  }
  std::cout << path << ": " << j["scans"].size() << " scans, " << withCommas(j["points"].get<std::size_t>())
            << " points, " << withCommas(j["readings"].get<std::size_t>()) << " readings, bounds " << point(j["bounds"][0]) << " to " << point(j["bounds"][1]) << " m\n";
  if (j.contains("truth")) std::cout << "  synthetic: the truth is a " << j["truth"].get<std::string>() << "\n";
  for (const auto& m : j["scans"])
    std::cout << "  " << m["name"].get<std::string>() << ": " << m["projection"].get<std::string>() << " "
              << m["width"].get<int>() << " x " << m["height"].get<int>() << ", "
              << withCommas(m["points"].get<std::size_t>()) << " points, "
              << withCommas(m["readings"].get<std::size_t>()) << " readings, ray spacing "
              << length(m["ray_spacing"].get<double>()) << ", sigma " << length(m["sigma"].get<double>())
              << (m.contains("angular_grid") ? ", " + angularGridText(m["angular_grid"]) : "")
              << (m["coloured"].get<bool>() ? ", coloured" : "") << "\n";
}

int runInfo(const InfoSettings& s) {
  nlohmann::json all = nlohmann::json::array();
  for (const std::string& path : s.paths) {
    enterPhase("reading");
    const bool vdb = std::filesystem::path(path).extension() == ".vdb";
    all.push_back(vdb ? describeVdb(path) : describeScans(path, s));
    // Reading a .vdb does not ask for a cancellation: a request made while
    // it read is answered before anything is printed.
    checkCancellation();
    if (!s.json) print(all.back());
  }
  if (s.json) std::cout << (all.size() == 1 ? all[0] : all).dump(2) << "\n";
  return kExitSuccess;
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
  auto s = std::make_shared<InfoSettings>();
  CLI::App* cmd = app.add_subcommand("info", "Describe a .vdb result or a set of scans");
  cmd->add_option("paths", s->paths, "A .vdb file, a Stanford .conf, a PTX or E57 file, a JSON manifest or a folder of depth frames")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--toward-scanner", s->towardScanner, "Stanford scans: direction toward the scanner, x,y,z");
  cmd->add_flag("--json", s->json, "Print as JSON");
  cmd->footer(
      "Examples:\n"
      "  levelfuse info bunny.vdb\n"
      "  levelfuse info bunny/bun.conf --json");
  return {cmd, [s] { return runInfo(*s); }};
}

}  // namespace levelfuse::cli

// levelfuse synth: synthetic range scans of a sphere, torus, mug, room or mesh.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace levelfuse::cli {
namespace {

using openvdb::Vec3d;

struct SynthSettings {
  std::string shape = "torus";
  std::string mesh;
  int views = 0;
  int resolution = 200;
  double noise = 0.0;
  double outliers = 0.0;
  std::uint64_t seed = 1;
  bool pinhole = false;
  std::string scanner = "parallel";
  std::string paint = "none";
  std::string output;
  bool json = false;
};

/// A triangle mesh from a PLY file (element vertex x, y, z; element face).
void readMeshPly(const std::string& path, std::vector<Vec3d>& points, std::vector<openvdb::Vec3I>& triangles) {
  const io::PlyData ply = io::readPly(path);
  const io::PlyElement* vertex = ply.element("vertex");
  const io::PlyElement* face = ply.element("face");
  if (!vertex || vertex->property("x") < 0 || vertex->property("y") < 0 || vertex->property("z") < 0)
    throw io::InputError(path, "no 'vertex' element with x, y and z");
  if (!face || (face->property("vertex_indices") < 0 && face->property("vertex_index") < 0))
    throw io::InputError(path, "no 'face' element with vertex_indices");
  const int x = vertex->property("x"), y = vertex->property("y"), z = vertex->property("z");
  for (std::size_t i = 0; i < vertex->count; ++i)
    points.emplace_back(vertex->values[x][i], vertex->values[y][i], vertex->values[z][i]);
  const int list = face->property("vertex_indices") >= 0 ? face->property("vertex_indices") : face->property("vertex_index");
  const std::vector<double>& items = face->values[list];
  const std::vector<std::size_t>& offsets = face->listOffsets[list];
  for (std::size_t f = 0; f < face->count; ++f) {
    const std::size_t begin = offsets[f], end = offsets[f + 1];
    for (std::size_t k = begin; k < end; ++k)
      if (!(items[k] >= 0.0 && items[k] < static_cast<double>(points.size())))
        throw io::InputError(path, "face " + std::to_string(f) + " points at a vertex that does not exist");
    for (std::size_t k = begin + 2; k < end; ++k)  // a fan of triangles
      triangles.emplace_back(static_cast<openvdb::Index32>(items[begin]), static_cast<openvdb::Index32>(items[k - 1]),
                             static_cast<openvdb::Index32>(items[k]));
  }
  if (triangles.empty()) throw io::InputError(path, "the mesh has no faces");
}

RangeMap::Kind scannerOf(const SynthSettings& s) {
  if (s.pinhole || s.scanner == "pinhole" || s.shape == "street") return RangeMap::Kind::kPinhole;
  return s.scanner == "spherical" || s.shape == "room" ? RangeMap::Kind::kSpherical : RangeMap::Kind::kOrthographic;
}

/// The views' sizes, "W x H pixels" if they all share one.
std::string pixelsOf(const std::vector<RangeMap>& maps) {
  for (const RangeMap& m : maps)
    if (m.width() != maps.front().width() || m.height() != maps.front().height()) return "views of several sizes";
  return std::to_string(maps.front().width()) + " x " + std::to_string(maps.front().height()) + " pixels";
}

/// The colours of --paint halves: the upper half of the scene red, the lower blue.
constexpr Rgb8 kUpperHalf{200, 40, 30}, kLowerHalf{30, 60, 200};

/// Paints every map's readings red above the horizontal plane through the
/// middle of all the readings, blue below.
void paintHalves(std::vector<RangeMap>& maps) {
  openvdb::BBoxd bounds;
  for (const RangeMap& m : maps) bounds.expand(m.readingBounds());
  const synth::SurfacePaint paint = synth::twoColours(bounds.getCenter(), Vec3d(0, 0, 1), kUpperHalf, kLowerHalf);
  for (RangeMap& m : maps) synth::paintReadings(m, paint);
}

int runSynth(const SynthSettings& s) {
  if (s.shape == "room" && (s.pinhole || s.scanner != "parallel") && s.scanner != "spherical")
    throw std::invalid_argument("synth: the room is scanned by spherical scanners (--scanner spherical)");
  if (s.shape == "street" && s.scanner != "parallel" && s.scanner != "pinhole")
    throw std::invalid_argument("synth: the street is filmed by depth cameras (--scanner pinhole)");
  synth::SceneOptions options;
  options.views = s.views;
  options.resolution = s.resolution;
  options.noise = s.noise;
  options.outliers = s.outliers;
  options.seed = s.seed;
  options.scanner = scannerOf(s);
  enterPhase("scanning");
  synth::Scene scene;
  if (!s.mesh.empty()) {
    std::vector<Vec3d> points;
    std::vector<openvdb::Vec3I> triangles;
    readMeshPly(s.mesh, points, triangles);
    scene = synth::meshScene(points, triangles, options);
  } else if (s.shape == "room") {
    scene = synth::roomScene(shapes::Room{}, options);
  } else if (s.shape == "street") {
    scene = synth::streetScene(options);
  } else {
    using Kind = shapes::AnalyticShape::Kind;
    const Kind kind = s.shape == "sphere" ? Kind::kSphere : s.shape == "torus" ? Kind::kTorus : Kind::kMug;
    scene = synth::analyticScene(synth::standardShape(kind), options);
  }
  if (s.paint == "halves") paintHalves(scene.maps);
  const std::vector<RangeMap>& maps = scene.maps;
  std::size_t readings = 0;
  for (const RangeMap& m : maps) readings += m.validCount();
  enterPhase("writing");
  io::OutputSet outputs;
  const std::string manifest = io::writeScanSet(outputs, s.output, maps, scene.truth);
  commitOutputs(outputs);

  if (s.json) {
    nlohmann::json j{{"shape", s.mesh.empty() ? s.shape : s.mesh},
                     {"views", maps.size()},
                     {"resolution", s.resolution},
                     {"projection", projectionName(options.scanner)},
                     {"readings", readings},
                     {"noise_sigma", scene.noiseSigma},
                     {"outlier_fraction", s.outliers},
                     {"paint", s.paint},
                     {"manifest", manifest}};
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "levelfuse synth: " << maps.size() << " " << projectionName(options.scanner) << " views of "
              << (s.mesh.empty() ? "a " + s.shape : s.mesh) << ", " << pixelsOf(maps) << ", " << withCommas(readings)
              << " readings\n"
              << "  noise: Gaussian sigma " << length(scene.noiseSigma) << " (" << fixed(100.0 * s.noise, 3)
              << "% of " << scene.sizeName << "), " << fixed(100.0 * s.outliers, 3) << "% outliers\n"
              << "  wrote " << manifest << " and " << maps.size() << " range images beside it\n";
  }
  return kExitSuccess;
}

}  // namespace

Command addSynthCommand(CLI::App& app) {
  auto s = std::make_shared<SynthSettings>();
  CLI::App* cmd = app.add_subcommand("synth", "Make synthetic range scans of a sphere, torus, mug, room or mesh");
  cmd->add_option("--shape", s->shape,
                  "Analytic shape (its truth goes into the manifest); the room (6 x 4 x 2.5 m, with a table, a "
                  "ball, a ring and a pillar) is scanned from three tripods by spherical scanners; the street (a "
                  "façade with bays, on the ground, half a metre more of it per view) is filmed by depth cameras "
                  "moving along it, each seeing about 2 m")
      ->check(CLI::IsMember({"sphere", "torus", "mug", "room", "street"}))
      ->capture_default_str();
  cmd->add_option("--mesh", s->mesh, "Scan a triangle mesh (.ply) instead")->check(CLI::ExistingFile);
  cmd->add_option("--views", s->views, "Number of views (default 6; 10 for the mug; 40 for the street)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--resolution", s->resolution,
                  "Pixels along each side of a view (spherical scanners: rays across the shape; the room's: rays "
                  "per quarter turn)")
      ->check(CLI::Range(8, 8192))
      ->capture_default_str();
  cmd->add_option("--noise", s->noise,
                  "Gaussian range noise as a fraction of the shape's size (sphere: diameter; torus: tube "
                  "diameter; mug: handle width; mesh: largest extent; room: height, at 1 m of range), as in the paper")
      ->check(numberIn(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--outliers", s->outliers, "Fraction of readings replaced by uniform outliers")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--seed", s->seed, "Seed of the noise")->capture_default_str();
  cmd->add_option("--scanner", s->scanner,
                  "parallel (laser stripes), pinhole (depth cameras) or spherical (terrestrial laser scanners, "
                  "noise growing with range)")
      ->check(CLI::IsMember({"parallel", "pinhole", "spherical"}))
      ->capture_default_str();
  cmd->add_option("--paint", s->paint,
                  "Colour the readings: halves (red above the middle of the scene, blue below; written as a colour "
                  "image beside each range image) or none")
      ->check(CLI::IsMember({"none", "halves"}))
      ->capture_default_str();
  cmd->add_flag("--pinhole", s->pinhole, "Depth cameras instead of parallel rays (--scanner pinhole)");
  cmd->add_option("-o,--output", s->output, "Folder for scans.json and the range images")->required();
  cmd->add_flag("--json", s->json, "Print the summary as JSON");
  cmd->footer(
      "Examples:\n"
      "  levelfuse synth --shape torus --noise 0.2 -o torus-scans     # the paper's Fig. 10\n"
      "  levelfuse synth --shape mug --noise 0.5 -o mug-scans         # Fig. 14\n"
      "  levelfuse synth --shape mug --outliers 0.01 -o mug-outliers  # Fig. 15\n"
      "  levelfuse synth --mesh part.ply --views 12 --pinhole -o part-scans\n"
      "  levelfuse synth --shape room --noise 0.0004 -o room-scans   # three tripods, 1 mm at 1 m\n"
      "  levelfuse synth --shape street --views 400 --resolution 160 --noise 0.003 -o street  # 200 m of depth video");
  return {cmd, [s] { return runSynth(*s); }};
}

}  // namespace levelfuse::cli

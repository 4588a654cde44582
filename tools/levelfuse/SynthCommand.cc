// levelfuse synth: synthetic range scans of a sphere, torus, mug or mesh.

#include "Commands.h"
#include "Support.h"

#include <levelfuse/io/InputError.h>
#include <levelfuse/io/Manifest.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/scan/Synth.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>

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

int runSynth(const SynthSettings& s) {
  // The shape, its size for the noise, and the views that see it all.
  std::optional<io::TruthShape> truth;
  std::function<double(const Vec3d&)> distance;
  std::vector<Vec3d> points;
  std::vector<openvdb::Vec3I> triangles;
  openvdb::BBoxd bounds;
  double size = 1.0;  // the noise is a fraction of this
  std::string sizeName;
  if (!s.mesh.empty()) {
    readMeshPly(s.mesh, points, triangles);
    for (const Vec3d& p : points) bounds.expand(p);
    size = bounds.extents()[bounds.maxExtent()];
    sizeName = "the mesh's largest extent";
  } else {
    truth = io::TruthShape();
    if (s.shape == "sphere") {
      truth->kind = io::TruthShape::Kind::kSphere;
      truth->sphere = shapes::Sphere{Vec3d(0.0), 1.0};
      bounds = openvdb::BBoxd(Vec3d(-1.0), Vec3d(1.0));
      size = 2.0;
      sizeName = "the diameter";
    } else if (s.shape == "torus") {
      truth->kind = io::TruthShape::Kind::kTorus;
      truth->torus = shapes::Torus{Vec3d(0.0), 1.0, 0.4};
      bounds = openvdb::BBoxd(Vec3d(-1.4, -1.4, -0.4), Vec3d(1.4, 1.4, 0.4));
      size = 0.8;
      sizeName = "the tube's diameter";
    } else {
      truth->kind = io::TruthShape::Kind::kMug;
      truth->mug = shapes::Mug{Vec3d(0.0, 0.0, -1.0)};
      bounds = openvdb::BBoxd(Vec3d(-1.0, -1.0, -1.0), Vec3d(1.0 + truth->mug.handleBend + truth->mug.handleRadius, 1.0, 1.0));
      size = 2.0 * truth->mug.handleRadius;
      sizeName = "the handle's width";
    }
    distance = [t = *truth](const Vec3d& p) { return t(p); };
  }
  const Vec3d centre = bounds.getCenter();
  const double extent = 1.2 * bounds.extents()[bounds.maxExtent()] + 0.2 * size;
  const int count = s.views > 0 ? s.views : (s.shape == "mug" && s.mesh.empty() ? 10 : 6);
  std::vector<synth::View> views;
  if (s.mesh.empty() && s.shape == "torus") {
    views = synth::ringViews(centre, extent, s.resolution, count, 40.0);
  } else if (s.mesh.empty() && s.shape == "mug" && count >= 3) {
    // Straight down into the cup and up at its base, the rest around it.
    views = synth::ringViews(centre, extent, s.resolution, count - 2, 30.0);
    views.push_back(synth::orthographicView(Vec3d(0, 0, -1), centre, extent, s.resolution, "top"));
    views.push_back(synth::orthographicView(Vec3d(0, 0, 1), centre, extent, s.resolution, "bottom"));
  } else {
    views = synth::viewsAround(centre, extent, s.resolution, count);
  }
  if (s.pinhole)
    for (synth::View& v : views) {
      const Vec3d forward = v.mapToWorld.transform3x3(Vec3d(0, 0, 1));
      v = synth::pinholeView(centre - forward * 2.5 * extent, centre, 25.0, s.resolution, s.resolution, v.name);
    }

  synth::Noise noise;
  noise.gaussianSigma = s.noise * size;
  noise.replacementFraction = s.outliers;
  const double sigma = std::max(noise.gaussianSigma, 1e-3 * size);  // the maps' stated noise
  std::vector<RangeMap> maps;
  std::size_t readings = 0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    noise.seed = s.seed + i;
    maps.push_back(s.mesh.empty() ? synth::renderDistanceFunction(distance, views[i], noise, sigma)
                                  : synth::renderMesh(points, triangles, views[i], noise, sigma));
    readings += maps.back().validCount();
  }
  const std::string manifest = io::writeScanSet(s.output, maps, truth);

  if (s.json) {
    nlohmann::json j{{"shape", s.mesh.empty() ? s.shape : s.mesh},
                     {"views", maps.size()},
                     {"resolution", s.resolution},
                     {"projection", s.pinhole ? "pinhole" : "orthographic"},
                     {"readings", readings},
                     {"noise_sigma", noise.gaussianSigma},
                     {"outlier_fraction", s.outliers},
                     {"manifest", manifest}};
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "levelfuse synth: " << maps.size() << " " << (s.pinhole ? "pinhole" : "orthographic") << " views of "
              << (s.mesh.empty() ? "a " + s.shape : s.mesh) << ", " << s.resolution << " x " << s.resolution
              << " pixels, " << withCommas(readings) << " readings\n"
              << "  noise: Gaussian sigma " << fixed(noise.gaussianSigma) << " (" << fixed(100.0 * s.noise, 3)
              << "% of " << sizeName << "), " << fixed(100.0 * s.outliers, 3) << "% outliers\n"
              << "  wrote " << manifest << " and " << maps.size() << " range images beside it\n";
  }
  return kExitSuccess;
}

}  // namespace

Command addSynthCommand(CLI::App& app) {
  auto s = std::make_shared<SynthSettings>();
  CLI::App* cmd = app.add_subcommand("synth", "Make synthetic range scans of a sphere, torus, mug or mesh");
  cmd->add_option("--shape", s->shape, "Analytic shape (its truth goes into the manifest)")
      ->check(CLI::IsMember({"sphere", "torus", "mug"}))
      ->capture_default_str();
  cmd->add_option("--mesh", s->mesh, "Scan a triangle mesh (.ply) instead")->check(CLI::ExistingFile);
  cmd->add_option("--views", s->views, "Number of views (default 6; 10 for the mug)")->check(CLI::Range(1, 1000));
  cmd->add_option("--resolution", s->resolution, "Pixels along each side of a view")
      ->check(CLI::Range(8, 8192))
      ->capture_default_str();
  cmd->add_option("--noise", s->noise,
                  "Gaussian range noise as a fraction of the shape's size (sphere: diameter; torus: tube "
                  "diameter; mug: handle width; mesh: largest extent), as in the paper")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--outliers", s->outliers, "Fraction of readings replaced by uniform outliers")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--seed", s->seed, "Seed of the noise")->capture_default_str();
  cmd->add_flag("--pinhole", s->pinhole, "Depth cameras instead of parallel rays");
  cmd->add_option("-o,--output", s->output, "Folder for scans.json and the range images")->required();
  cmd->add_flag("--json", s->json, "Print the summary as JSON");
  cmd->footer(
      "Examples:\n"
      "  levelfuse synth --shape torus --noise 0.2 -o torus-scans     # the paper's Fig. 10\n"
      "  levelfuse synth --shape mug --noise 0.5 -o mug-scans         # Fig. 14\n"
      "  levelfuse synth --shape mug --outliers 0.01 -o mug-outliers  # Fig. 15\n"
      "  levelfuse synth --mesh part.ply --views 12 --pinhole -o part-scans");
  return {cmd, [s] { return runSynth(*s); }};
}

}  // namespace levelfuse::cli

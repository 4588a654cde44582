// levelfuse mesh: a level set's zero set as a triangle mesh.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/io/MeshFile.h>
#include <levelfuse/io/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/scan/SurfaceColour.h>

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <optional>

namespace levelfuse::cli {
namespace {

struct MeshSettings {
  std::string input, output, grid;
  double adaptivity = 0.0;
  std::optional<bool> trimUnseen;  // none: if the level set is of a scene
  bool json = false;
};

/// The grid named `name` that `levelfuse reconstruct` wrote beside `levelSet`
/// (its weight, its colour), if any.
template <typename GridT>
typename GridT::Ptr gridBeside(const openvdb::GridPtrVec& grids, const openvdb::FloatGrid& levelSet,
                               const std::string& name) {
  for (const openvdb::GridBase::Ptr& base : grids) {
    const auto grid = openvdb::GridBase::grid<GridT>(base);
    if (!grid || grid->getName() != name) continue;
    const auto surface = grid->template getMetadata<openvdb::StringMetadata>("levelfuse_surface");
    if (surface && surface->value() == levelSet.getName()) return grid;
  }
  return nullptr;
}

int runMesh(const MeshSettings& s) {
  requireOutputs({s.output}, {s.input});
  io::requireMeshFileName(s.output);
  enterPhase("loading");
  const openvdb::GridPtrVecPtr grids = io::readVdb(s.input);
  openvdb::FloatGrid::Ptr levelSet;
  for (const openvdb::GridBase::Ptr& base : *grids) {
    const auto grid = openvdb::GridBase::grid<openvdb::FloatGrid>(base);
    if (!grid || grid->getGridClass() != openvdb::GRID_LEVEL_SET) continue;
    if (s.grid.empty() || grid->getName() == s.grid) {
      levelSet = grid;
      break;
    }
  }
  if (!levelSet)
    throw std::runtime_error(s.input + ": no float level set" + (s.grid.empty() ? "" : " named '" + s.grid + "'") +
                             " (see levelfuse info " + s.input + ")");
  if (const std::string problem = levelSetProblem(*levelSet); !problem.empty())
    throw std::runtime_error(s.input + ": " + problem);
  const openvdb::FloatGrid::Ptr weight = gridBeside<openvdb::FloatGrid>(*grids, *levelSet, kWeightGridName);
  const openvdb::Vec3fGrid::Ptr colour = gridBeside<openvdb::Vec3fGrid>(*grids, *levelSet, kColourGridName);
  const auto scene = levelSet->getMetadata<openvdb::BoolMetadata>("levelfuse_scene");
  const bool trim = trimsUnseen(weight && scene && scene->value(), s.trimUnseen);
  if (trim && !weight)
    throw std::runtime_error(s.input + ": no weight grid for '" + levelSet->getName() +
                             "' to trim by (levelfuse reconstruct writes one beside the level set); "
                             "drop --trim-unseen");
  enterPhase("meshing");
  const TriangleMesh mesh = meshShown(*levelSet, trim ? weight.get() : nullptr, s.adaptivity, colour.get());
  enterPhase("writing");
  io::OutputSet outputs;
  io::writeMesh(outputs, s.output, mesh);
  commitOutputs(outputs);
  if (s.json) {
    std::cout << nlohmann::json{{"input", s.input}, {"grid", levelSet->getName()}, {"output", s.output},
                                {"vertices", mesh.vertexCount()}, {"triangles", mesh.triangleCount()},
                                {"area", mesh.area()}, {"volume", mesh.volume()}, {"trimmed_unseen", trim},
                                {"coloured", mesh.hasColours()}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "levelfuse mesh: '" << levelSet->getName() << "' from " << s.input << ": "
              << withCommas(mesh.vertexCount()) << " vertices, " << withCommas(mesh.triangleCount())
              << " triangles, area " << area(mesh.area()) << ", volume " << volume(mesh.volume())
              << (trim ? " (unseen parts left out: an open mesh)" : "")
              << (mesh.hasColours() ? ", coloured" : "") << "\n"
              << "  wrote " << s.output << "\n";
  }
  return kExitSuccess;
}

}  // namespace

Command addMeshCommand(CLI::App& app) {
  auto s = std::make_shared<MeshSettings>();
  CLI::App* cmd = app.add_subcommand("mesh", "Turn a level set (.vdb) into a triangle mesh (.ply or .obj)");
  cmd->add_option("input", s->input, "A .vdb file")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", s->output, "The mesh, .ply (binary) or .obj")->required();
  cmd->add_option("--grid", s->grid, "Name of the level set in the file (default: the first)");
  cmd->add_option("--adaptivity", s->adaptivity, "0: uniform triangles; up to 1: fewer where the surface is flat")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
  addTrimUnseenOptions(cmd, s->trimUnseen, "Mesh",
                       "Default: on for a level set of depth frames (a scene) with its weight grid beside it.");
  cmd->add_flag("--json", s->json, "Print the summary as JSON");
  cmd->footer("Examples:\n  levelfuse mesh bunny.vdb -o bunny.ply\n  levelfuse mesh bunny.vdb --adaptivity 0.3 -o bunny.obj");
  return {cmd, [s] { return runMesh(*s); }};
}

}  // namespace levelfuse::cli

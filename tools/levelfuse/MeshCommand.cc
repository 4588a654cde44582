// levelfuse mesh: a level set's zero set as a triangle mesh.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"

#include <levelfuse/io/MeshFile.h>
#include <levelfuse/io/VdbFile.h>
#include <levelfuse/levelset/Mesh.h>

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace levelfuse::cli {
namespace {

struct MeshSettings {
  std::string input, output, grid;
  double adaptivity = 0.0;
  bool json = false;
};

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
  enterPhase("meshing");
  const TriangleMesh mesh = meshFromLevelSet(*levelSet, s.adaptivity);
  enterPhase("writing");
  io::OutputSet outputs;
  io::writeMesh(outputs, s.output, mesh);
  commitOutputs(outputs);
  if (s.json) {
    std::cout << nlohmann::json{{"input", s.input}, {"grid", levelSet->getName()}, {"output", s.output},
                                {"vertices", mesh.vertexCount()}, {"triangles", mesh.triangleCount()},
                                {"area", mesh.area()}, {"volume", mesh.volume()}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "levelfuse mesh: '" << levelSet->getName() << "' from " << s.input << ": "
              << withCommas(mesh.vertexCount()) << " vertices, " << withCommas(mesh.triangleCount())
              << " triangles, area " << fixed(mesh.area()) << ", volume " << fixed(mesh.volume()) << "\n"
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
  cmd->add_flag("--json", s->json, "Print the summary as JSON");
  cmd->footer("Examples:\n  levelfuse mesh bunny.vdb -o bunny.ply\n  levelfuse mesh bunny.vdb --adaptivity 0.3 -o bunny.obj");
  return {cmd, [s] { return runMesh(*s); }};
}

}  // namespace levelfuse::cli

// levelfuse mesh: a level set's zero set as a triangle mesh.

#include "Cancellation.h"
#include "Commands.h"
#include "Support.h"
#include "Units.h"

#include <levelfuse/io/outputs/MeshFile.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/scan/SurfaceColour.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace levelfuse::cli {
namespace {

struct MeshSettings {
  std::vector<std::string> inputs;
  std::string output, grid;
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

/// A level set and the grids levelfuse reconstruct wrote beside it.
struct Surface {
  openvdb::FloatGrid::Ptr levelSet, weight;
  openvdb::Vec3fGrid::Ptr colour;
};

/// The level set named `name` (the first, if none is named) in `file`, with its weight and colour.
Surface surfaceIn(const std::string& file, const std::string& name) {
  const openvdb::GridPtrVecPtr grids = io::readVdb(file);
  Surface surface;
  for (const openvdb::GridBase::Ptr& base : *grids) {
    const auto grid = openvdb::GridBase::grid<openvdb::FloatGrid>(base);
    if (!grid || grid->getGridClass() != openvdb::GRID_LEVEL_SET) continue;
    if (name.empty() || grid->getName() == name) {
      surface.levelSet = grid;
      break;
    }
  }
  if (!surface.levelSet)
    throw std::runtime_error(file + ": no float level set" + (name.empty() ? "" : " named '" + name + "'") +
                             " (see levelfuse info " + file + ")");
  if (const std::string problem = levelSetProblem(*surface.levelSet); !problem.empty())
    throw std::runtime_error(file + ": " + problem);
  surface.weight = gridBeside<openvdb::FloatGrid>(*grids, *surface.levelSet, kWeightGridName);
  surface.colour = gridBeside<openvdb::Vec3fGrid>(*grids, *surface.levelSet, kColourGridName);
  return surface;
}

/// Which piece of how many `levelSet` is (levelSetPieceOf); throws, naming
/// `file`, for a level set that is no piece.
std::pair<int, int> pieceOf(const openvdb::FloatGrid& levelSet, const std::string& file) {
  const std::optional<std::pair<int, int>> piece = levelSetPieceOf(levelSet);
  if (!piece)
    throw std::runtime_error(file + ": '" + levelSet.getName() +
                             "' is a whole level set, not a piece of one (levelfuse reconstruct --pieces writes "
                             "pieces): give one whole level set, or every piece of one");
  return *piece;
}

/// The whole level set of its pieces (one per file, each written by a rank of
/// levelfuse reconstruct --pieces), with their weight and colour: every piece
/// once, on one transform, or an error naming the file.
Surface surfaceOfPieces(const std::vector<std::string>& files, const std::string& name) {
  std::vector<Surface> pieces;
  std::vector<bool> seen(files.size(), false);
  for (const std::string& file : files) {
    Surface piece = surfaceIn(file, name);
    const auto [index, count] = pieceOf(*piece.levelSet, file);
    const std::string which = "piece " + std::to_string(index + 1) + " of " + std::to_string(count);
    if (count != static_cast<int>(files.size()) || index < 0 || index >= count)
      throw std::runtime_error(file + ": " + which + ", but " + std::to_string(files.size()) +
                               " files were given: give every piece, once");
    if (seen[static_cast<std::size_t>(index)]) throw std::runtime_error(file + ": " + which + " was given twice");
    seen[static_cast<std::size_t>(index)] = true;
    if (!pieces.empty() && piece.levelSet->transform() != pieces.front().levelSet->transform())
      throw std::runtime_error(file + ": its voxels are not those of " + files.front() + ": pieces of another run");
    pieces.push_back(std::move(piece));
  }
  Surface whole;
  whole.levelSet = pieces.front().levelSet->copyWithNewTree();
  forgetLevelSetPiece(*whole.levelSet);
  const bool weighed = std::all_of(pieces.begin(), pieces.end(), [](const Surface& p) { return p.weight != nullptr; });
  const bool coloured = std::all_of(pieces.begin(), pieces.end(), [](const Surface& p) { return p.colour != nullptr; });
  if (weighed) whole.weight = pieces.front().weight->copyWithNewTree();
  if (coloured) whole.colour = pieces.front().colour->copyWithNewTree();
  for (Surface& piece : pieces) {
    moveLevelSetLeaves(*piece.levelSet, SlabBounds{}, *whole.levelSet);
    if (weighed) moveAllLeaves(*piece.weight, *whole.weight);
    if (coloured) moveAllLeaves(*piece.colour, *whole.colour);
    piece = Surface();
  }
  closeAssembledLevelSet(*whole.levelSet);
  return whole;
}

int runMesh(const MeshSettings& s) {
  requireOutputs({s.output}, s.inputs);
  io::requireMeshFileName(s.output);
  enterPhase("loading");
  const Surface surface = s.inputs.size() == 1 ? surfaceIn(s.inputs.front(), s.grid) : surfaceOfPieces(s.inputs, s.grid);
  const openvdb::FloatGrid& levelSet = *surface.levelSet;
  const std::string from = joined(s.inputs);
  const auto scene = levelSet.getMetadata<openvdb::BoolMetadata>("levelfuse_scene");
  const bool trim = trimsUnseen(surface.weight && scene && scene->value(), s.trimUnseen);
  if (trim && !surface.weight)
    throw std::runtime_error(from + ": no weight grid for '" + levelSet.getName() +
                             "' to trim by (levelfuse reconstruct writes one beside the level set); "
                             "drop --trim-unseen");
  enterPhase("meshing");
  const TriangleMesh mesh = meshShown(levelSet, trim ? surface.weight.get() : nullptr, s.adaptivity, surface.colour.get());
  enterPhase("writing");
  io::OutputSet outputs;
  io::writeMesh(outputs, s.output, mesh);
  commitOutputs(outputs);
  if (s.json) {
    std::cout << nlohmann::json{{"input", s.inputs.front()}, {"inputs", s.inputs}, {"grid", levelSet.getName()},
                                {"output", s.output}, {"vertices", mesh.vertexCount()},
                                {"triangles", mesh.triangleCount()}, {"area", mesh.area()}, {"volume", mesh.volume()},
                                {"trimmed_unseen", trim}, {"coloured", mesh.hasColours()}}
                     .dump(2)
              << "\n";
  } else {
    std::cout << "levelfuse mesh: '" << levelSet.getName() << "' from " << from
              << (s.inputs.size() > 1 ? " (" + std::to_string(s.inputs.size()) + " pieces put together)" : "") << ": "
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
  cmd->add_option("inputs", s->inputs,
                  "A .vdb file, or every piece of one level set (levelfuse reconstruct --pieces), put together first")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", s->output, "The mesh, .ply (binary) or .obj")->required();
  cmd->add_option("--grid", s->grid, "Name of the level set in the file (default: the first)");
  cmd->add_option("--adaptivity", s->adaptivity, "0: uniform triangles; up to 1: fewer where the surface is flat")
      ->check(numberIn(0.0, 1.0))
      ->capture_default_str();
  addTrimUnseenOptions(cmd, s->trimUnseen, "Mesh",
                       "Default: on for a level set of depth frames (a scene) with its weight grid beside it.");
  cmd->add_flag("--json", s->json, "Print the summary as JSON");
  cmd->footer(
      "Examples:\n  levelfuse mesh bunny.vdb -o bunny.ply\n  levelfuse mesh bunny.vdb --adaptivity 0.3 -o bunny.obj\n"
      "  levelfuse mesh bunny.0-of-4.vdb bunny.1-of-4.vdb bunny.2-of-4.vdb bunny.3-of-4.vdb -o bunny.ply");
  return {cmd, [s] { return runMesh(*s); }};
}

}  // namespace levelfuse::cli

// levelfuse: a reconstruction of scans read and held packed, as the converter
// and the Python module run it: on a fusion of the scans when the data term
// comes from grids (the scans stay packed, integrated once), else on the scans
// themselves; and how its outputs show and describe the surface.
#pragma once

#include <levelfuse/core/Interrupter.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/RangeMap.h>

#include <openvdb/openvdb.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace levelfuse {

struct ScansReconstruction {
  std::unique_ptr<Fusion> fusion;  ///< set when the data term comes from grids
  std::unique_ptr<Reconstructor> reconstructor;
  RangeMapSequence scans;  ///< the scans, one at a time (for the fit)
  PackedScans kept;        ///< a fusion's scans once its grids are let go

  /// Once the surface and its weight are made, a fusion's grids are let go
  /// (before the fit and the mesh, which would otherwise hold them at their
  /// peak), and their memory handed back (returnFreedMemory); its scans stay
  /// for the fit. The reconstructor is asked nothing more that needs the
  /// fusion: its settings and summary are its own.
  void letTheGridsGo();
};

/// `scans` made ready to reconstruct with `settings` (resolved from the
/// scans' summary: resolveReconstructionSettings). With a data term from grids
/// the scans are integrated here, `integrated` told after each how many of how
/// many are in. Throws InsufficientMemory for grids that would not fit,
/// Interrupted if `interrupter` stops the integration. For a `team` that will
/// share the reconstruction (Reconstructor::run), the fusion holds this
/// process's slab of the data alone where the team shares the data in slabs
/// (recon/SharedData.h): the slab `cut` if it is given. `scans` may be a part
/// of the team's scans, their summary the whole team's and `settings` those
/// of the whole (a team's process reading the scans its slab needs:
/// recon/TeamScans.h).
ScansReconstruction prepareReconstruction(PackedScans scans, const ReconstructionSettings& settings,
                                          const std::function<void(std::size_t, std::size_t)>& integrated = {},
                                          const Interrupter& interrupter = {}, const SlabTeam* team = nullptr,
                                          const SharedDataSlab* cut = nullptr);

/// Whether meshes and previews leave out the surface no scan observed
/// (recon/SurfaceWeight.h): as `asked`, else for scenes only (scans of a
/// scene: ScanSummary::aScene, or a level set's levelfuse_scene metadata).
bool trimsUnseen(bool scene, std::optional<bool> asked = std::nullopt);

/// The zero set of `levelSet` as a mesh (meshFromLevelSet), without what no
/// scan observed where `trimBy`, its weight grid (recon/SurfaceWeight.h), is
/// given: the triangles below kObservedWeight are left out (trimMesh); its
/// vertices coloured by `colour` where it is given (paintMesh).
TriangleMesh meshShown(const openvdb::FloatGrid& levelSet, const openvdb::FloatGrid* trimBy,
                       double adaptivity = 0.0, const openvdb::Vec3fGrid* colour = nullptr);

/// The zero crossings of `levelSet` (levelset/ZeroCrossings.h) that its mesh
/// shows: without those where `trimBy`, its weight grid, interpolated
/// trilinearly, is below kObservedWeight. What measures of the surface shown
/// (an error against a true scene) are taken at.
std::vector<openvdb::Vec3d> zeroCrossingsShown(const openvdb::FloatGrid& levelSet, const openvdb::FloatGrid* trimBy);

/// `options` for the picture of a surface: seen through `camera`'s eyes if it
/// is given (a scene's first frame, io::seenByFrame), and without what no scan
/// observed where `trimBy`, its weight grid, is given.
io::PreviewOptions previewShown(io::PreviewOptions options, const RangeMap* camera,
                                openvdb::FloatGrid::ConstPtr trimBy);

/// The run's inputs (joined with ", "), its method and whether the scans are a
/// scene, in the surface's levelfuse_* metadata beside the parameters
/// (Reconstructor::run's).
void describeInputs(openvdb::FloatGrid& surface, const std::vector<std::string>& inputs, bool linear, bool scene);

}  // namespace levelfuse

// levelfuse: a reconstruction of scans read and held packed.

#include <levelfuse/recon/ScansReconstruction.h>

#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/levelset/MeshTrim.h>
#include <levelfuse/levelset/ZeroCrossings.h>
#include <levelfuse/recon/SurfaceWeight.h>
#include <levelfuse/scan/SurfaceColour.h>

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <utility>

namespace levelfuse {

void ScansReconstruction::letTheGridsGo() {
  if (!fusion) return;
  kept = fusion->takeScans();
  fusion.reset();
  returnFreedMemory();  // the grids, built on the worker threads' heaps
  scans = kept.unpacked();
}

ScansReconstruction prepareReconstruction(PackedScans scans, const ReconstructionSettings& settings,
                                          const std::function<void(std::size_t, std::size_t)>& integrated,
                                          const Interrupter& interrupter, const SlabTeam* team,
                                          const SharedDataSlab* cut) {
  ScansReconstruction r;
  if (settings.dataTerm == DataTermSource::kGrids) {
    r.fusion = fusePackedScans(std::move(scans), settings, integrated, interrupter, team, cut);
    r.reconstructor = std::make_unique<Reconstructor>(*r.fusion, settings);
    r.scans = r.fusion->scans();
    return r;
  }
  std::vector<RangeMap> maps;
  maps.reserve(scans.maps.size());
  for (const PackedRangeMap& p : scans.maps) maps.push_back(p.unpack());
  scans = PackedScans();
  r.reconstructor = std::make_unique<Reconstructor>(std::move(maps), settings);
  r.scans = rangeMapsOf(r.reconstructor->maps());
  return r;
}

bool trimsUnseen(bool scene, std::optional<bool> asked) { return asked.value_or(scene); }

TriangleMesh meshShown(const openvdb::FloatGrid& levelSet, const openvdb::FloatGrid* trimBy, double adaptivity,
                       const openvdb::Vec3fGrid* colour) {
  TriangleMesh mesh = trimBy ? meshFromLevelSet(levelSet, adaptivity, *voxelsToMesh(*trimBy, kObservedWeight))
                             : meshFromLevelSet(levelSet, adaptivity);
  if (trimBy) mesh = trimMesh(mesh, *trimBy, kObservedWeight);
  returnFreedMemory();  // the mesher's tables, built on the worker threads' heaps
  if (colour) paintMesh(mesh, *colour);
  return mesh;
}

std::vector<openvdb::Vec3d> zeroCrossingsShown(const openvdb::FloatGrid& levelSet, const openvdb::FloatGrid* trimBy) {
  std::vector<openvdb::Vec3d> crossings = zeroCrossings(levelSet);
  if (!trimBy) return crossings;
  const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> weight(*trimBy);
  crossings.erase(std::remove_if(crossings.begin(), crossings.end(),
                                 [&](const openvdb::Vec3d& p) { return !(weight.wsSample(p) >= kObservedWeight); }),
                  crossings.end());
  return crossings;
}

io::PreviewOptions previewShown(io::PreviewOptions options, const RangeMap* camera,
                                openvdb::FloatGrid::ConstPtr trimBy) {
  if (camera) options = io::seenByFrame(*camera, options);
  if (trimBy) {
    options.weight = std::move(trimBy);
    options.minWeight = kObservedWeight;
  }
  return options;
}

void describeInputs(openvdb::FloatGrid& surface, const std::vector<std::string>& inputs, bool linear, bool scene) {
  std::string joined;
  for (const std::string& input : inputs) joined += (joined.empty() ? "" : ", ") + input;
  surface.insertMeta("levelfuse_inputs", openvdb::StringMetadata(joined));
  surface.insertMeta("levelfuse_method",
                     openvdb::StringMetadata(linear ? "linear solution (zero set of g)" : "MAP level-set evolution"));
  surface.insertMeta("levelfuse_scene", openvdb::BoolMetadata(scene));
}

}  // namespace levelfuse

// levelfuse: every public header in one include, for a program that uses the
// whole library. (Each header also stands alone; include only what you use to
// keep compile times down: OpenVDB's headers are heavy.)
//
// A consumer's first reconstruction, from scans on disk to a .vdb file:
//
//   openvdb::initialize();
//   levelfuse::Reconstructor reconstructor(levelfuse::io::loadScans("bunny/bun.conf"));
//   levelfuse::ReconstructionResult result = reconstructor.run();
//   levelfuse::io::writeVdb("bunny.vdb", {result.levelSet, result.weight});
#pragma once

#include <levelfuse/Version.h>

#include <levelfuse/core/DebugCheck.h>
#include <levelfuse/core/FreedMemory.h>
#include <levelfuse/core/Interrupter.h>
#include <levelfuse/core/MadeAhead.h>
#include <levelfuse/core/Median.h>
#include <levelfuse/core/MemoryBudget.h>
#include <levelfuse/core/Parallel.h>
#include <levelfuse/core/PeakMemory.h>
#include <levelfuse/core/PhaseClock.h>

#include <levelfuse/geometry/NearestTriangle.h>
#include <levelfuse/geometry/Shapes.h>

#include <levelfuse/io/AtomicWrite.h>
#include <levelfuse/io/InputError.h>
#include <levelfuse/io/InputFile.h>
#include <levelfuse/io/MemoryBudget.h>
#include <levelfuse/io/Ply.h>
#include <levelfuse/io/TextRecords.h>
#include <levelfuse/io/images/ColourImages.h>
#include <levelfuse/io/images/DepthImages.h>
#include <levelfuse/io/outputs/MeshFile.h>
#include <levelfuse/io/outputs/Preview.h>
#include <levelfuse/io/scans/DepthFrames.h>
#include <levelfuse/io/scans/E57Scans.h>
#include <levelfuse/io/scans/LoadProgress.h>
#include <levelfuse/io/scans/Manifest.h>
#include <levelfuse/io/scans/PointScans.h>
#include <levelfuse/io/scans/PtxScan.h>
#include <levelfuse/io/scans/PtxScans.h>
#include <levelfuse/io/scans/ScanLoadOptions.h>
#include <levelfuse/io/scans/Scans.h>
#include <levelfuse/io/scans/StanfordScans.h>
#include <levelfuse/io/scans/StationGrid.h>
#include <levelfuse/io/scans/TumScans.h>
#include <levelfuse/io/vdb/VdbFile.h>

#include <levelfuse/levelset/Background.h>
#include <levelfuse/levelset/Components.h>
#include <levelfuse/levelset/DenseField.h>
#include <levelfuse/levelset/DenseFieldStep.h>
#include <levelfuse/levelset/Invariants.h>
#include <levelfuse/levelset/LeafNodeWidth.h>
#include <levelfuse/levelset/LevelSetFromFunction.h>
#include <levelfuse/levelset/LevelSetPieces.h>
#include <levelfuse/levelset/Mesh.h>
#include <levelfuse/levelset/MeshTrim.h>
#include <levelfuse/levelset/Refine.h>
#include <levelfuse/levelset/RequireLevelSet.h>
#include <levelfuse/levelset/SlabField.h>
#include <levelfuse/levelset/SlabFieldStep.h>
#include <levelfuse/levelset/SlabTeam.h>
#include <levelfuse/levelset/SparseField.h>
#include <levelfuse/levelset/SparseFieldOptions.h>
#include <levelfuse/levelset/SparseFieldStats.h>
#include <levelfuse/levelset/SparseFieldStep.h>
#include <levelfuse/levelset/SpeedTerms.h>
#include <levelfuse/levelset/Stencil.h>
#include <levelfuse/levelset/StepResult.h>
#include <levelfuse/levelset/StepTally.h>
#include <levelfuse/levelset/TilesBesideLeaves.h>
#include <levelfuse/levelset/TimeStep.h>
#include <levelfuse/levelset/VoxelNormals.h>
#include <levelfuse/levelset/ZeroCrossings.h>

#include <levelfuse/recon/DataFit.h>
#include <levelfuse/recon/DataSpeed.h>
#include <levelfuse/recon/Fusion.h>
#include <levelfuse/recon/FusionSettings.h>
#include <levelfuse/recon/HeldOutFrames.h>
#include <levelfuse/recon/MemoryPlan.h>
#include <levelfuse/recon/ReconstructionOptions.h>
#include <levelfuse/recon/Reconstructor.h>
#include <levelfuse/recon/RunSummary.h>
#include <levelfuse/recon/ScansReconstruction.h>
#include <levelfuse/recon/SharedData.h>
#include <levelfuse/recon/TeamScans.h>
#include <levelfuse/recon/SurfaceRoughness.h>
#include <levelfuse/recon/SurfaceWeight.h>

#include <levelfuse/scan/AccumulationCost.h>
#include <levelfuse/scan/CarvingMemo.h>
#include <levelfuse/scan/Colour.h>
#include <levelfuse/scan/DataTermGrids.h>
#include <levelfuse/scan/DataWindow.h>
#include <levelfuse/scan/DepthRaster.h>
#include <levelfuse/scan/ForceField.h>
#include <levelfuse/scan/LaserSweep.h>
#include <levelfuse/scan/MapProjection.h>
#include <levelfuse/scan/PackedRangeMap.h>
#include <levelfuse/scan/PixelFlags.h>
#include <levelfuse/scan/RangeMap.h>
#include <levelfuse/scan/ScanSummary.h>
#include <levelfuse/scan/SightBins.h>
#include <levelfuse/scan/SphereAngles.h>
#include <levelfuse/scan/SphericalScan.h>
#include <levelfuse/scan/SurfaceColour.h>

#include <levelfuse/synth/Scenes.h>
#include <levelfuse/synth/Synth.h>

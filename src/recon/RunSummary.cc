// levelfuse: a run's summary as JSON.

#include <levelfuse/recon/RunSummary.h>

#include <levelfuse/core/PeakMemory.h>

#include <nlohmann/json.hpp>

namespace levelfuse {
namespace {

nlohmann::json gridsJson(const std::vector<LevelReport>& levels) {
  nlohmann::json grids = nlohmann::json::array();
  for (const LevelReport& l : levels)
    grids.push_back({{"voxel_size", l.voxelSize},
                     {"iterations", l.iterations},
                     {"converged", l.converged},
                     {"settled", l.settled},
                     {"simulated_time", l.simulatedTime},
                     {"seconds", l.seconds},
                     {"active_set_voxels", l.activeSetVoxels},
                     {"band_voxels", l.bandVoxels},
                     {"engine_bytes", l.engineBytes}});
  return grids;
}

nlohmann::json phasesJson(const std::vector<PhaseTime>& phases) {
  nlohmann::json json = nlohmann::json::array();
  for (const PhaseTime& p : phases) json.push_back({{"name", p.name}, {"seconds", p.seconds}, {"cpu_seconds", p.cpuSeconds}});
  return json;
}

/// The sparse-field engine's settings the run used.
nlohmann::json engineJson(const SparseFieldOptions& e) {
  return {{"layers", e.layers},
          {"max_step_change", e.maxStepChange},
          {"curvature_step_limit", e.curvatureStepLimit},
          {"stiffness_step_limit", e.stiffnessStepLimit},
          {"grain_size", e.grainSize}};
}

/// Null if the fit was not measured.
nlohmann::json fitJson(const RunSummary& s) {
  if (!s.fit) return nullptr;
  const DataFit& fit = *s.fit;
  return {{"points", fit.readings}, {"stride", s.fitStride}, {"mean", fit.mean},
          {"rms", fit.rms},         {"median", fit.median},  {"p90", fit.p90},
          {"p99", fit.p99},         {"within_voxel", fit.withinVoxel}, {"beyond_band", fit.beyondBand}};
}

/// Null where nothing was written.
nlohmann::json fileJson(const std::string& path) { return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(path); }

nlohmann::json outputsJson(const RunSummary& s) {
  const nlohmann::json vdb = s.levelSetPieces.empty() ? fileJson(s.levelSetFile) : nlohmann::json(s.levelSetPieces);
  return {{"vdb", vdb}, {"mesh", fileJson(s.meshFile)}, {"preview", fileJson(s.previewFile)}};
}

nlohmann::json processesJson(const std::vector<ProcessFacts>& processes) {
  nlohmann::json json = nlohmann::json::array();
  for (const ProcessFacts& f : processes)
    json.push_back({{"seconds", f.seconds},
                    {"peak_memory_bytes", f.peakBytes},
                    {"peak_engine_bytes", f.engineBytes},
                    {"leaf_nodes", f.leafNodes},
                    {"ghost_bytes_sent", f.ghostBytes},
                    {"data_term_bytes", f.dataTermBytes},
                    {"scans_held", f.scansHeld}});
  return json;
}

}  // namespace

void recordProcessUsage(RunSummary& summary) {
  summary.peakMemoryBytes = peakResidentBytes();
  summary.cpuSeconds = processCpuSeconds();
}

std::string runSummaryJson(const RunSummary& s) {
  nlohmann::json j{{"inputs", s.inputs},
                   {"scans", s.scans},
                   {"points", s.points},
                   {"readings", s.readings},
                   {"method", s.linear ? "linear" : "evolution"},
                   {"scene", s.scene},
                   {"voxel_size", s.settings.voxelSize},
                   {"levels", s.settings.levels},
                   {"beta", s.settings.beta},
                   {"epsilon", s.settings.epsilon},
                   {"engine", engineJson(s.settings.engine)},
                   {"grids", gridsJson(s.levels)},
                   {"narrow_band_voxels", s.narrowBandVoxels},
                   {"peak_engine_bytes", s.peakEngineBytes},
                   {"data_term_bytes", s.dataTermBytes},
                   {"peak_memory_bytes", s.peakMemoryBytes},
                   {"fit", fitJson(s)},
                   {"seconds", s.seconds},
                   {"cpu_seconds", s.cpuSeconds},
                   {"phases", phasesJson(s.phases)},
                   {"outputs", outputsJson(s)},
                   {"triangles", s.triangles},
                   {"trimmed_unseen", s.trimmedUnseen}};
  if (s.processes.size() > 1) j["ranks"] = processesJson(s.processes);
  if (s.truth)
    j["truth"] = {{"shape", s.truth->shape},
                  {"rms_error", s.truth->rms},
                  {"measured_on", s.truth->whereSeen ? "the surface seen" : "the whole surface"},
                  {"rms_error_voxels", s.truth->rms / s.settings.voxelSize}};
  return j.dump(2);
}

}  // namespace levelfuse

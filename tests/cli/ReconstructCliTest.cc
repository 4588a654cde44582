// levelfuse synth, reconstruct, info and mesh, run as a user runs them.

#include "CliSupport.h"
#include "SignalledRun.h"
#include "support/TestSupport.h"

#include <levelfuse/io/Ply.h>
#include <levelfuse/io/vdb/VdbFile.h>
#include <levelfuse/levelset/Components.h>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <iterator>
#include <thread>
#include <utility>
#include <vector>

#include <sys/wait.h>

namespace levelfuse {
namespace {

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

openvdb::FloatGrid::Ptr readSurface(const std::string& path) {
  const openvdb::GridPtrVecPtr grids = io::readVdb(path);
  return openvdb::GridBase::grid<openvdb::FloatGrid>(grids->at(0));
}

class ReconstructCli : public Cli {
 protected:
  /// Synthetic scans of a sphere of radius 1, 80 pixels a side.
  std::string sphereScans(const std::string& extra = "") {
    const CliRun run = levelfuse("synth --shape sphere --resolution 80 " + extra + " -o " + path("scans"));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    return path("scans/scans.json");
  }
};

TEST_F(ReconstructCli, SynthThenReconstructFindsTheSphere) {
  const std::string scans = sphereScans("--noise 0.02");
  const CliRun info = levelfuse("info --json " + scans);
  ASSERT_EQ(info.exitCode, 0) << info.output;
  EXPECT_EQ(jsonOf(info)["scans"].size(), 6u);
  EXPECT_EQ(jsonOf(info)["truth"], "sphere");

  const CliRun run = levelfuse("reconstruct " + scans + " -o " + path("s.vdb") + " --mesh " + path("s.ply") +
                               " --preview " + path("s.png") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.output;
  const nlohmann::json j = jsonOf(run);
  EXPECT_EQ(j["scans"], 6);
  EXPECT_EQ(j["method"], "evolution");
  // Noise of 2% of the diameter (0.04): the surface lies far closer to the truth.
  EXPECT_LT(j["truth"]["rms_error"].get<double>(), 0.01);
  EXPECT_LT(j["fit"]["beyond_band"].get<double>(), 0.01);  // no holes where the scans saw the sphere
  EXPECT_GT(j["triangles"].get<std::size_t>(), 1000u);

  const openvdb::FloatGrid::Ptr surface = readSurface(path("s.vdb"));
  EXPECT_EQ(surface->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_EQ(insideComponents(*surface), 1);
  EXPECT_EQ(surface->metaValue<std::string>("levelfuse_inputs"), scans);
  const io::PlyData mesh = io::readPly(path("s.ply"));
  EXPECT_EQ(mesh.element("face")->count, j["triangles"].get<std::size_t>());
  EXPECT_TRUE(fs::exists(path("s.png")));
  const CliRun vdbInfo = levelfuse("info " + path("s.vdb"));
  EXPECT_NE(vdbInfo.output.find("levelfuse_beta"), std::string::npos) << vdbInfo.output;
}

TEST_F(ReconstructCli, OutputsAreBitIdenticalAcrossRunsAndThreadCounts) {
  const std::string scans = sphereScans("--noise 0.05");
  for (const std::string run : {"one", "two", "again"}) {
    const std::string threads = run == "one" ? "1" : "2";
    ASSERT_EQ(levelfuse("reconstruct -q --threads " + threads + " " + scans + " -o " + path(run + ".vdb") +
                        " --mesh " + path(run + ".ply"))
                  .exitCode,
              0);
  }
  std::string why;
  EXPECT_TRUE(test::identical(*readSurface(path("one.vdb")), *readSurface(path("two.vdb")), &why)) << why;
  for (const std::string ext : {".vdb", ".ply"}) {
    const std::string one = fileBytes(path("one" + ext));
    ASSERT_FALSE(one.empty());
    EXPECT_TRUE(one == fileBytes(path("two" + ext))) << ext << ": 1 and 2 threads differ";
    EXPECT_TRUE(one == fileBytes(path("again" + ext))) << ext << ": two runs differ";
  }
}

TEST_F(ReconstructCli, LinearSolutionAndMeshCommand) {
  const std::string scans = sphereScans();
  const CliRun run = levelfuse("reconstruct --linear --json " + scans + " -o " + path("lin.vdb"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_EQ(jsonOf(run)["method"], "linear");
  const CliRun mesh = levelfuse("mesh --json " + path("lin.vdb") + " -o " + path("lin.obj"));
  ASSERT_EQ(mesh.exitCode, 0) << mesh.output;
  EXPECT_NEAR(jsonOf(mesh)["volume"].get<double>(), 4.0 / 3.0 * M_PI, 0.05);
  std::ifstream obj(path("lin.obj"));
  std::string first;
  std::getline(obj, first);
  EXPECT_EQ(first.rfind("# written by levelfuse", 0), 0u) << first;
}

TEST_F(ReconstructCli, OneProcesssOnePieceIsTheWholeAndWhatNeedsItWholeIsRefused) {
  // --pieces names each rank's file; one process writes the one piece of
  // one, the whole level set (tests/mpi/cli_mpi_test.sh runs ranks).
  const std::string scans = sphereScans();
  CliRun run = levelfuse("reconstruct " + scans + " --voxel-size 0.05 -q -o " + path("whole.vdb"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  run = levelfuse("reconstruct " + scans + " --voxel-size 0.05 --pieces -o " + path("p.vdb"));
  ASSERT_EQ(run.exitCode, 0) << run.output;
  EXPECT_NE(run.output.find("wrote " + path("p.0-of-1.vdb") + " (a piece of the closed level set, 1 in all"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("fit to the points: not measured, the surface is in pieces"), std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(path("p.vdb")));
  const auto whole = openvdb::gridPtrCast<openvdb::FloatGrid>((*io::readVdb(path("whole.vdb")))[0]);
  const auto piece = openvdb::gridPtrCast<openvdb::FloatGrid>((*io::readVdb(path("p.0-of-1.vdb")))[0]);
  ASSERT_TRUE(whole && piece);
  std::string why;
  EXPECT_TRUE(test::identical(*whole, *piece, &why)) << why;
  EXPECT_EQ(piece->metaValue<openvdb::Int32>("levelfuse_piece"), 0);
  EXPECT_EQ(piece->metaValue<openvdb::Int32>("levelfuse_pieces"), 1);
  EXPECT_FALSE(piece->getMetadata<openvdb::Int32Metadata>("levelfuse_piece_begin_x"));
  // A mesh or preview needs the whole surface, the linear solution is not
  // shared, and pieces are files of -o's name: refused before any work.
  const std::pair<std::string, std::string> refused[] = {
      {" --pieces -o " + path("q.vdb") + " --mesh " + path("q.ply"), "a mesh or preview needs it whole"},
      {" --pieces --preview " + path("q.png"), "--pieces writes the level set in pieces: give -o result.vdb"},
      {" --pieces --linear -o " + path("q.vdb"), "--linear has no evolution"}};
  for (const auto& [options, message] : refused) {
    run = levelfuse("reconstruct " + scans + options);
    EXPECT_EQ(run.exitCode, 1) << options << ": " << run.output;
    EXPECT_NE(run.output.find(message), std::string::npos) << options << ": " << run.output;
  }
  for (const char* file : {"q.vdb", "q.0-of-1.vdb", "q.ply", "q.png"}) EXPECT_FALSE(fs::exists(path(file))) << file;
}

TEST_F(ReconstructCli, TextSummariesGiveLengthsWithUnitsAndJsonInMetres) {
  const std::string scans = sphereScans();
  const CliRun text = levelfuse("reconstruct --linear --voxel-size 0.05 " + scans + " -o " + path("u.vdb"));
  ASSERT_EQ(text.exitCode, 0) << text.output;
  EXPECT_NE(text.output.find("voxel 5.0 cm,"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find(": mean "), std::string::npos) << text.output;
  EXPECT_NE(text.output.find(" mm, median "), std::string::npos) << text.output;
  const CliRun json = levelfuse("reconstruct --linear --json --voxel-size 0.05 " + scans + " -o " + path("j.vdb"));
  ASSERT_EQ(json.exitCode, 0) << json.output;
  EXPECT_DOUBLE_EQ(jsonOf(json)["voxel_size"].get<double>(), 0.05);
  const CliRun info = levelfuse("info " + path("u.vdb"));
  EXPECT_NE(info.output.find("voxel 5.0 cm,"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("background 15 cm,"), std::string::npos) << info.output;
  const CliRun mesh = levelfuse("mesh " + path("u.vdb") + " -o " + path("u.ply"));
  EXPECT_NE(mesh.output.find(" m², volume "), std::string::npos) << mesh.output;
}

TEST_F(ReconstructCli, BadInputFailsClearlyAndWritesNothing) {
  std::ofstream(path("broken.json")) << "{ \"scans\": [ { \"format\": \"depth-png\" } ] }";
  CliRun run = levelfuse("reconstruct " + path("broken.json") + " -o " + path("out.vdb"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find(path("broken.json")), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("missing 'file'"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out.vdb")));

  std::ofstream(path("notes.txt")) << "hello";
  run = levelfuse("reconstruct " + path("notes.txt") + " -o " + path("out.vdb"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("not a kind of scan"), std::string::npos) << run.output;

  const std::string scans = sphereScans();
  run = levelfuse("reconstruct " + scans);  // no output asked for
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("nothing to write"), std::string::npos) << run.output;
  run = levelfuse("reconstruct " + scans + " -o " + path("no/such/folder/out.vdb"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("does not exist"), std::string::npos) << run.output;
  run = levelfuse("reconstruct " + scans + " --mesh " + path("out.stl"));
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find(".ply or .obj"), std::string::npos) << run.output;
  run = levelfuse("reconstruct " + scans + " -o /dev/null");  // never replaced by a file
  EXPECT_EQ(run.exitCode, 1);
  EXPECT_NE(run.output.find("not a regular file"), std::string::npos) << run.output;
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A malformed preview direction is a usage error: the run never starts.
  run = levelfuse("reconstruct " + scans + " --view 1,2 -o " + path("out.vdb") + " --preview " + path("out.png"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  EXPECT_NE(run.output.find("'1,2' is not three numbers x,y,z"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out.vdb")));
  run = levelfuse("reconstruct " + scans + " --beta -1 -o " + path("out.vdb"));
  EXPECT_EQ(run.exitCode, 2) << run.output;
  // A voxel size that needs more memory than allowed stops before it allocates.
  run = levelfuse("reconstruct " + scans + " --voxel-size 0.002 --max-memory 0.05 -o " + path("out.vdb"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("more than the 51.2 MiB levelfuse may use: choose a voxel size (--voxel-size) of at least"),
            std::string::npos)
      << run.output;
  run = levelfuse("reconstruct --linear " + scans + " --voxel-size 0.002 --max-memory 0.05 -o " + path("out.vdb"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("choose a voxel size (--voxel-size) of at least"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(path("out.vdb")));
  EXPECT_FALSE(fs::exists(path("out.stl")));
}

/// True once process `pid` catches SIGINT (Linux: the SigCgt mask in /proc/<pid>/status).
bool catchesSigint(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigCgt:", 0) != 0) continue;
    const unsigned long long mask = std::stoull(line.substr(7), nullptr, 16);
    return (mask >> (SIGINT - 1)) & 1ull;
  }
  return false;
}

TEST_F(ReconstructCli, InterruptedRunWritesNothing) {
  const std::string scans = sphereScans("--noise 0.05");
  const std::string log = path("log.txt");
  ChildRun run({"reconstruct", "--max-iterations", "100000", "--tolerance", "1e-12", "--voxel-size", "0.01", scans,
                "-o", path("out.vdb")},
               log);
  ASSERT_TRUE(run.started());
  const pid_t pid = run.pid();

  // SIGINT once the run listens for it (however slowly it starts, under a sanitizer say), and a
  // moment later, while the level set evolves: the run stops between iterations.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!catchesSigint(pid) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(catchesSigint(pid)) << "levelfuse never installed its SIGINT handler";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_TRUE(run.send(SIGINT));
  const int status = run.wait();
  const std::string output = run.output();
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_EQ(WEXITSTATUS(status), 130) << output;
  EXPECT_NE(output.find("interrupted while evolving; nothing written"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(path("out.vdb")));
  fs::remove(log);
  for (const auto& entry : fs::directory_iterator(mDir)) EXPECT_EQ(entry.path().extension(), "") << entry.path();
}

}  // namespace
}  // namespace levelfuse

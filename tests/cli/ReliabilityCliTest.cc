// What the CLI promises beyond bad input: outputs committed together or not at
// all (a full disk, an output that is an input), inputs that would block,
// cancellation in every phase, numeric options checked at parse time.

#include "CliSupport.h"
#include "SignalledRun.h"
#include "support/SmallDisk.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

namespace levelfuse {
namespace {

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class ReliabilityCli : public Cli {
 protected:
  /// Small synthetic scans of a sphere: a fast run.
  std::string scans() {
    const CliRun run = levelfuse("synth --shape sphere --resolution 40 -o " + path("scans"));
    EXPECT_EQ(run.exitCode, 0) << run.output;
    return path("scans/scans.json");
  }
  /// Files directly in the test's folder (the scans' folder not counted).
  std::size_t outputsInDir() const { return filesInDir() - (fs::exists(mDir / "scans") ? 1 : 0); }
};

/// LEVELFUSE_TEST_SIGNAL_AT=<phase> makes the CLI send itself SIGINT as the phase starts.
CliRun interruptedAt(const std::string& phase, const std::string& arguments) {
  return levelfuse(arguments, "LEVELFUSE_TEST_SIGNAL_AT=" + phase);
}

TEST_F(ReliabilityCli, SigintInEveryPhaseExits130AndWritesNothing) {
  const std::string input = scans();
  const std::string outputs = " -o " + path("o.vdb") + " --mesh " + path("o.ply") + " --preview " + path("o.png");
  const std::vector<std::pair<std::string, std::string>> runs{
      {"loading", "reconstruct --linear " + input + outputs},
      {"solving", "reconstruct --linear " + input + outputs},
      {"evolving", "reconstruct " + input + outputs},
      {"measuring", "reconstruct --linear " + input + outputs},
      {"meshing", "reconstruct --linear " + input + outputs},
      {"writing", "reconstruct --linear " + input + outputs}};
  for (const auto& [phase, arguments] : runs) {
    const CliRun run = interruptedAt(phase, arguments);
    EXPECT_EQ(run.exitCode, 130) << phase << ": " << run.output;
    EXPECT_EQ(run.output, "levelfuse reconstruct: interrupted while " + phase + "; nothing written\n") << phase;
    EXPECT_EQ(outputsInDir(), 0u) << phase;
  }
  // More than 32 scans: their data term is integrated into grids, a phase of its own.
  ASSERT_EQ(levelfuse("synth --shape sphere --resolution 24 --views 40 -o " + path("many")).exitCode, 0);
  const CliRun integrating = interruptedAt("integrating", "reconstruct " + path("many/scans.json") + outputs);
  EXPECT_EQ(integrating.exitCode, 130) << integrating.output;
  EXPECT_EQ(integrating.output, "levelfuse reconstruct: interrupted while integrating; nothing written\n");
  EXPECT_EQ(outputsInDir(), 1u);  // the scans' folder "many" alone
  ASSERT_EQ(levelfuse("reconstruct --linear -q " + input + " -o " + path("in.vdb")).exitCode, 0);
  for (const std::string phase : {"loading", "meshing", "writing"}) {
    const CliRun run = interruptedAt(phase, "mesh " + path("in.vdb") + " -o " + path("m.ply"));
    EXPECT_EQ(run.exitCode, 130) << phase << ": " << run.output;
    EXPECT_EQ(run.output, "levelfuse mesh: interrupted while " + phase + "; nothing written\n") << phase;
    EXPECT_FALSE(fs::exists(path("m.ply"))) << phase;
  }
  // info writes no file; a request pending as it reads a .vdb stops it before it prints.
  const CliRun info = interruptedAt("reading", "info " + path("in.vdb"));
  EXPECT_EQ(info.exitCode, 130) << info.output;
  EXPECT_EQ(info.output, "levelfuse info: interrupted while reading; nothing written\n");
  for (const std::string phase : {"scanning", "writing"}) {
    const CliRun run = interruptedAt(phase, "synth --shape torus --resolution 32 -o " + path("more"));
    EXPECT_EQ(run.exitCode, 130) << phase << ": " << run.output;
    EXPECT_FALSE(fs::exists(path("more/scans.json"))) << phase;
    EXPECT_FALSE(fs::exists(path("more/scan0.pfm"))) << phase;
  }
}

/// A command sent `signal` `delay` after it started: it ends by the signal (sent before its
/// handler was installed) or says it was interrupted and exits 130, and `output` is not written.
void expectStoppedBy(int signal, std::chrono::milliseconds delay, const std::vector<std::string>& command,
                     const std::string& output, const std::string& log) {
  const std::string what = command.front() + " sent signal " + std::to_string(signal) + " after " +
                           std::to_string(delay.count()) + " ms";
  ChildRun run(command, log);
  ASSERT_TRUE(run.started()) << what;
  std::this_thread::sleep_for(delay);
  ASSERT_TRUE(run.send(signal)) << what << ": it had ended already: make its work longer\n" << run.output();
  const int status = run.wait();
  if (WIFSIGNALED(status)) {
    EXPECT_EQ(WTERMSIG(status), signal) << what;
  } else {
    EXPECT_EQ(WEXITSTATUS(status), 130) << what << "\n" << run.output();
    EXPECT_NE(run.output().find("levelfuse " + command.front() + ": interrupted while "), std::string::npos)
        << what << "\n" << run.output();
  }
  EXPECT_FALSE(fs::exists(output)) << what;
}

TEST_F(ReliabilityCli, ASignalAtAnyMomentStopsEveryCommandAndWritesNothing) {
  ASSERT_EQ(levelfuse("synth --shape sphere --resolution 200 -o " + path("scans")).exitCode, 0);
  const std::string input = path("scans/scans.json");
  ASSERT_EQ(levelfuse("reconstruct --linear -q " + input + " --voxel-size 0.01 -o " + path("in.vdb")).exitCode, 0);
  const std::string log = path("log.txt");
  const std::vector<std::pair<std::vector<std::string>, std::string>> commands{
      {{"reconstruct", input, "--voxel-size", "0.01", "-o", path("o.vdb")}, path("o.vdb")},
      {{"synth", "--shape", "torus", "--resolution", "400", "-o", path("more")}, path("more/scans.json")},
      {{"info", input, path("in.vdb"), "--json"}, ""},
      {{"mesh", path("in.vdb"), "-o", path("m.ply")}, path("m.ply")},
      {{"evolve", "--shape", "dumbbell", "--resolution", "100", "-o", path("e.vdb")}, path("e.vdb")}};
  for (const auto& [command, output] : commands) {
    for (const int ms : {0, 10, 50}) expectStoppedBy(SIGINT, std::chrono::milliseconds(ms), command, output, log);
    expectStoppedBy(SIGTERM, std::chrono::milliseconds(10), command, output, log);
  }
}

TEST_F(ReliabilityCli, ASignalIgnoredFromTheStartStaysIgnored) {
  // As a non-interactive shell starts `levelfuse ... &`: Ctrl-C at the terminal is not for it,
  // neither while it starts nor later.
  ASSERT_EQ(levelfuse("synth --shape sphere --resolution 40 -o " + path("scans")).exitCode, 0);
  ChildRun run({"reconstruct", "--linear", path("scans/scans.json"), "-o", path("o.vdb")}, path("log.txt"),
               ChildRun::Signals::kIgnored);
  ASSERT_TRUE(run.started());
  std::this_thread::sleep_for(std::chrono::milliseconds(10));
  run.send(SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  run.send(SIGINT);
  const int status = run.wait();
  ASSERT_TRUE(WIFEXITED(status)) << run.output();
  EXPECT_EQ(WEXITSTATUS(status), 0) << run.output();
  EXPECT_TRUE(fs::exists(path("o.vdb")));
}

TEST_F(ReliabilityCli, AnOutputThatIsAnInputIsRefusedBeforeAnyWork) {
  const std::string input = scans();
  const std::string manifest = contents(input), scan = contents(path("scans/scan0.pfm"));
  fs::create_symlink(input, path("link.vdb"));
  fs::create_hard_link(path("scans/scan0.pfm"), path("hard.ply"));
  for (const std::string& arguments :
       {"reconstruct --linear " + input + " -o " + input, "reconstruct --linear " + input + " -o " + path("link.vdb"),
        "reconstruct --linear " + input + " --mesh " + path("hard.ply"),
        "reconstruct --linear " + input + " --preview " + path("scans/scan0.pfm")}) {
    const CliRun run = levelfuse(arguments);
    EXPECT_EQ(run.exitCode, 1) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find("it is an input of this run"), std::string::npos) << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  }
  EXPECT_EQ(contents(input), manifest);
  EXPECT_EQ(contents(path("scans/scan0.pfm")), scan);
  EXPECT_TRUE(fs::is_symlink(path("link.vdb")));
  ASSERT_EQ(levelfuse("reconstruct --linear -q " + input + " -o " + path("in.vdb")).exitCode, 0);
  fs::create_hard_link(path("in.vdb"), path("same.obj"));
  const CliRun mesh = levelfuse("mesh " + path("in.vdb") + " -o " + path("same.obj"));
  EXPECT_EQ(mesh.exitCode, 1) << mesh.output;
  EXPECT_NE(mesh.output.find("it is an input of this run"), std::string::npos) << mesh.output;
}

TEST_F(ReliabilityCli, AFifoAsInputIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo(path("scans.conf").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo(path("x.vdb").c_str(), 0600), 0);
  for (const std::string& arguments : {"reconstruct " + path("scans.conf") + " -o " + path("o.vdb"),
                                       "info " + path("x.vdb"), "mesh " + path("x.vdb") + " -o " + path("o.ply")}) {
    const CliRun run = levelfuse(arguments);
    EXPECT_EQ(run.exitCode, 1) << arguments << "\n" << run.output;
    EXPECT_NE(run.output.find("is a FIFO (named pipe)"), std::string::npos) << run.output;
  }
  EXPECT_FALSE(fs::exists(path("o.vdb")));
  EXPECT_FALSE(fs::exists(path("o.ply")));
}

TEST_F(ReliabilityCli, NumericOptionsAreCheckedAtParseTime) {
  const std::string input = scans();
  const std::string reconstruct = "reconstruct " + input + " -o " + path("o.vdb") + " ";
  const std::vector<std::string> bad{
      reconstruct + "--voxel-size nan", reconstruct + "--beta nan",       reconstruct + "--epsilon nan",
      reconstruct + "--tolerance nan",  reconstruct + "--depth-scale nan", reconstruct + "--sigma nan",
      reconstruct + "--max-memory nan", reconstruct + "--voxel-size inf",  reconstruct + "--beta -1",
      reconstruct + "--tolerance 0",    reconstruct + "--depth-scale 2",   reconstruct + "--view 1,nan,0",
      reconstruct + "--voxel-size 0",   reconstruct + "--levels 0",        reconstruct + "--epsilon 0",
      "mesh " + path("x.vdb") + " -o " + path("m.ply") + " --adaptivity nan",
      "evolve -o " + path("e.vdb") + " --beta nan",       "evolve -o " + path("e.vdb") + " --time nan",
      "evolve -o " + path("e.vdb") + " --speed inf",      "synth -o " + path("s") + " --noise nan",
      "synth -o " + path("s") + " --outliers 2"};
  for (const std::string& arguments : bad) {
    const CliRun run = levelfuse(arguments);
    EXPECT_EQ(run.exitCode, 2) << arguments << "\n" << run.output;
  }
  EXPECT_EQ(outputsInDir(), 0u);
  const CliRun help = levelfuse("reconstruct --help");
  for (const std::string range : {"--voxel-size FLOAT:in (0, 1e+06]", "--beta FLOAT:in [0, 1000]",
                                  "--depth-scale FLOAT:in (0, 1]", "--tolerance FLOAT:in (0, 1000]"})
    EXPECT_NE(help.output.find(range), std::string::npos) << range << "\n" << help.output;
  // Iteration limits below the default minimum work: the minimum follows the maximum.
  for (const std::string limit : {"1", "2", "3"}) {
    const CliRun run = levelfuse("reconstruct -q " + input + " --max-iterations " + limit + " -o " + path("o.vdb"));
    EXPECT_EQ(run.exitCode, 0) << limit << ": " << run.output;
  }
}

/// One line naming the input and the problem, exit 1 and nothing written.
void expectOneLineRefusal(const CliRun& run, const std::string& input, const std::string& fragment) {
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_EQ(run.output.rfind("levelfuse reconstruct: error: " + input + ": ", 0), 0u) << run.output;
  EXPECT_NE(run.output.find(fragment), std::string::npos) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
}

TEST_F(ReliabilityCli, ParametersAreCheckedAgainstTheDataBeforeTheWork) {
  const std::string input = scans();
  const std::string outputs = " -o " + path("o.vdb") + " --mesh " + path("o.ply");
  // A window wider than the data (the sphere spans 2 units): the kernel killed this run for lack of memory.
  expectOneLineRefusal(levelfuse("reconstruct " + input + " --epsilon 1e6" + outputs), input,
                       "a window width epsilon of 1e+06 is wider than the data, which span 2: a reading would speak "
                       "for the whole scene; choose a window width (--epsilon) of at most 2");
  // A window within the data that reaches too many leaves for the memory allowed: the estimate says which voxel
  // size fits, before the data term is accumulated.
  const CliRun wide = levelfuse("reconstruct --linear " + input + " --epsilon 1.5 --max-memory 0.01" + outputs);
  expectOneLineRefusal(wide, input, "the data term on a grid of voxel size ");
  const std::string advice =
      "more than the 10.2 MiB levelfuse may use: choose a voxel size (--voxel-size) of at least 0.14";
  EXPECT_NE(wide.output.find(advice), std::string::npos) << wide.output;
  EXPECT_EQ(outputsInDir(), 0u);
}

TEST_F(ReliabilityCli, OutOfMemoryIsOneLineWhereverItHappens) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizers reserve more address space than the limit this test sets";
#else
  const std::string input = scans();
  // The budget says 100 GiB, the address space holds 200 MB: allocations fail wherever they are, in TBB's tasks
  // and in OpenVDB's trees too.
  const std::string command = "sh -c 'ulimit -v 200000; exec " + std::string(LEVELFUSE_CLI) + " reconstruct -q " +
                              input + " --voxel-size 0.005 --max-memory 100 -o " + path("o.vdb") + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof(buffer), pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  ASSERT_TRUE(WIFEXITED(status)) << output;
  EXPECT_EQ(WEXITSTATUS(status), 1) << output;
  EXPECT_EQ(output.rfind("levelfuse reconstruct: error: out of memory while ", 0), 0u) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  EXPECT_EQ(outputsInDir(), 0u);
#endif
}

TEST_F(ReliabilityCli, ReadingsInOnePlaneAreReadingsToo) {
  // A depth frame of a wall square to the camera: info counted its 64 readings, reconstruct said there were none.
  std::string pfm = "Pf\n8 8\n-1\n";
  const float depth = 1.0f;
  for (int i = 0; i < 64; ++i) pfm.append(reinterpret_cast<const char*>(&depth), sizeof(depth));
  std::ofstream(path("wall.pfm"), std::ios::binary) << pfm;
  std::ofstream(path("wall.json")) << R"({"scans": [{"format": "depth-pfm", "file": "wall.pfm",
    "intrinsics": {"fx": 8, "fy": 8, "cx": 3.5, "cy": 3.5}, "pose": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}]})";
  const CliRun info = levelfuse("info " + path("wall.json"));
  EXPECT_NE(info.output.find("64 readings"), std::string::npos) << info.output;
  const CliRun run = levelfuse("reconstruct --linear -q " + path("wall.json") + " -o " + path("wall.vdb"));
  EXPECT_EQ(run.exitCode, 0) << run.output;
  EXPECT_TRUE(fs::exists(path("wall.vdb")));
}

/// A full disk: exit 1 naming the file, no partial file, the file that would
/// have been replaced untouched, and no other output of the run replaced.
TEST_F(ReliabilityCli, AFullDiskFailsTheWholeRun) {
  test::SmallDisk disk;
  if (!disk.mounted()) GTEST_SKIP() << disk.reason();
  const std::string input = scans();
  std::ofstream(disk.path("keep.vdb")) << "old";
  std::ofstream(path("keep.vdb")) << "old";
  disk.fill();
  const std::size_t files = disk.fileCount();
  CliRun run = levelfuse("reconstruct --linear " + input + " -o " + disk.path("keep.vdb"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find("cannot write '" + disk.path("keep.vdb") + "'"), std::string::npos) << run.output;
  EXPECT_EQ(contents(disk.path("keep.vdb")), "old");
  EXPECT_EQ(disk.fileCount(), files);

  run = levelfuse("reconstruct --linear " + input + " -o " + path("keep.vdb") + " --mesh " + disk.path("x.ply"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_NE(run.output.find(disk.path("x.ply")), std::string::npos) << run.output;
  EXPECT_EQ(contents(path("keep.vdb")), "old");  // the other output was not committed
  EXPECT_EQ(disk.fileCount(), files);
  EXPECT_EQ(outputsInDir(), 1u);

  // libpng's own words about the failed write are part of the one line, never a line of their own.
  run = levelfuse("reconstruct --linear " + input + " --preview " + disk.path("x.png"));
  EXPECT_EQ(run.exitCode, 1) << run.output;
  EXPECT_EQ(run.output.rfind("levelfuse reconstruct: error: ", 0), 0u) << run.output;
  EXPECT_NE(run.output.find(disk.path("x.png")), std::string::npos) << run.output;
  EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;
  EXPECT_EQ(disk.fileCount(), files);
}

}  // namespace
}  // namespace levelfuse

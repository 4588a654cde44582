// Running the levelfuse converter as a child process that is sent a signal, as
// a terminal's Ctrl-C or a job scheduler's SIGTERM would send it.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern char** environ;

namespace levelfuse {

/// A converter process started with SIGINT and SIGTERM at their default
/// actions (whatever the test runner was started with), stdout and stderr to
/// `log`, or with both ignored, as a non-interactive shell starts a command in
/// the background.
class ChildRun {
 public:
  enum class Signals { kDefault, kIgnored };

  ChildRun(std::vector<std::string> arguments, const std::string& log, Signals signals = Signals::kDefault)
      : mLog(log) {
    arguments.insert(arguments.begin(), LEVELFUSE_CLI);
    std::vector<char*> argv;
    for (std::string& a : arguments) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t both;
    sigemptyset(&both);
    sigaddset(&both, SIGINT);
    sigaddset(&both, SIGTERM);
    struct sigaction ignore {}, previousInt {}, previousTerm {};
    ignore.sa_handler = SIG_IGN;
    if (signals == Signals::kDefault) {
      posix_spawnattr_setsigdefault(&attributes, &both);
      posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
    } else {
      // An ignored disposition is inherited: this process ignores both for the spawn.
      sigaction(SIGINT, &ignore, &previousInt);
      sigaction(SIGTERM, &ignore, &previousTerm);
    }
    mStarted = posix_spawn(&mPid, argv[0], &files, &attributes, argv.data(), environ) == 0;
    if (signals == Signals::kIgnored) {
      sigaction(SIGINT, &previousInt, nullptr);
      sigaction(SIGTERM, &previousTerm, nullptr);
    }
    posix_spawnattr_destroy(&attributes);
    posix_spawn_file_actions_destroy(&files);
  }
  ChildRun(const ChildRun&) = delete;
  ChildRun& operator=(const ChildRun&) = delete;
  ~ChildRun() {
    if (mStarted && !mEnded) wait();
  }

  bool started() const { return mStarted; }
  pid_t pid() const { return mPid; }

  /// Sends `signal` if the process still runs; false if it had ended already.
  bool send(int signal) {
    if (!mStarted || mEnded) return false;
    int status = 0;
    if (waitpid(mPid, &status, WNOHANG) == mPid) {
      mEnded = true;
      mStatus = status;
      return false;
    }
    return kill(mPid, signal) == 0;
  }

  /// Waits for the process to end: its wait status.
  int wait() {
    if (!mEnded && mStarted) {
      while (waitpid(mPid, &mStatus, 0) == -1 && errno == EINTR) {
      }
      mEnded = true;
    }
    return mStatus;
  }

  /// What the process wrote to stdout and stderr.
  std::string output() const {
    std::ifstream in(mLog, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }

 private:
  std::string mLog;
  pid_t mPid = 0;
  bool mStarted = false;
  bool mEnded = false;
  int mStatus = 0;
};

}  // namespace levelfuse

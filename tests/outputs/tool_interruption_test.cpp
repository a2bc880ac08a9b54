// Ctrl-C (SIGINT), SIGTERM (a job scheduler's stop) and SIGHUP end the tool
// by the same signal - shells report 130, 143 and 129 - after it has
// removed whatever it had staged: a run cut short leaves no output and no
// temporary file, and the files that were at its output paths stay as they
// were. The signals are real, sent to real runs.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "small_inputs.hpp"

extern char** environ;

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

/// `stvd` started in the background, stdout and stderr into files.
class RunningTool {
 public:
  RunningTool(const std::vector<std::string>& arguments, const std::string& capture) : capture_(capture) {
    std::vector<std::string> words{toolExecutable()};
    words.insert(words.end(), arguments.begin(), arguments.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, (capture + ".out").c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (capture + ".err").c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    EXPECT_EQ(posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);
  }
  ~RunningTool() {
    if (pid_ > 0 && !ended_) {
      ::kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  void signal(int s) const { ::kill(pid_, s); }
  /// The wait status once it has ended.
  int wait() {
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    ended_ = true;
    return status;
  }
  bool running() const { return waitpid(pid_, nullptr, WNOHANG) == 0; }
  std::string err() const {
    std::ifstream in(capture_ + ".err");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  std::string capture_;
  pid_t pid_ = -1;
  bool ended_ = false;
};

class ToolInterruption : public SmallInputsTest {
 protected:
  const std::string brain = sampleFile("dti_tensor_dipy5d.nii.gz");

  /// The staging folder in out/ holding at least one file, or "".
  std::string stagingWithAFile() const {
    for (const auto& entry : fs::directory_iterator(path("out")))
      if (entry.path().filename().string().rfind(".stvd-staging-", 0) == 0 && entry.is_directory() &&
          !fs::is_empty(entry.path()))
        return entry.path().string();
    return "";
  }
};

TEST_F(ToolInterruption, SigtermDuringTheComputationEndsTheRunAsTheShellSees143) {
  // Lanthier's method with M = 2 takes about 3 s on the brain; the signal
  // comes after 1 s, through bash as a job scheduler would send it.
  const ToolRun run = runToolInBash("\"$0\" \"$@\" & pid=$!; sleep 1; kill -TERM $pid; wait $pid; echo \"status $?\"",
                                    {"distance", brain, "--seed-voxel", "55,54,15", "--method", "lanthier", "--steiner",
                                     "2", "-o", out("d.nii.gz"), "--stats", out("d.json")});
  EXPECT_EQ(run.out, "status 143\n") << run.err;
  EXPECT_EQ(run.err, "stvd: interrupted (SIGTERM)\n");
  EXPECT_TRUE(listFolder(path("out")).empty());
}

TEST_F(ToolInterruption, SigintWhileWritingRemovesTheStagedOutputsAndKeepsTheEarlierOnes) {
  const std::vector<std::string> arguments{"distance", brain, "--seed-voxel", "55,54,15", "-o", out("d.nii.gz"),
                                           "--stats", out("d.json"), "-q"};
  ASSERT_EQ(runTool(arguments).exitCode, 0);
  for (const auto& entry : fs::directory_iterator(path("out")))
    std::ofstream(entry.path(), std::ios::app) << "\nan earlier output\n";
  const FolderSnapshot before = snapshot(path("out"));
  // The run is stopped (SIGSTOP) as soon as a staged file exists, then sent
  // SIGINT and let go on. Should the commit win the race nonetheless (the
  // write takes tens of milliseconds, the watching a fraction of one), the
  // attempt is repeated.
  for (int attempt = 0; attempt < 5; ++attempt) {
    RunningTool tool(arguments, path("capture"));
    std::string staging;
    while (staging.empty() && tool.running()) staging = stagingWithAFile();
    if (staging.empty()) {  // it finished first
      tool.wait();
      continue;
    }
    tool.signal(SIGSTOP);
    if (!fs::exists(staging)) {  // committed between the look and the stop
      tool.signal(SIGCONT);
      tool.wait();
      continue;
    }
    tool.signal(SIGINT);
    tool.signal(SIGCONT);
    const int status = tool.wait();
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit code " << WEXITSTATUS(status) << ": " << tool.err();
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    EXPECT_EQ(tool.err(), "stvd: interrupted (SIGINT)\n");
    EXPECT_TRUE(snapshot(path("out")) == before) << "out/ changed";
    return;
  }
  FAIL() << "the run was never caught while writing";
}

TEST_F(ToolInterruption, TetrahedralizeStopsItsMeshingChildToo) {
  if (!withTetrahedralize()) GTEST_SKIP() << "built without TetGen";
  // About 4 s of meshing in the child stvd-tetrahedralize; SIGTERM goes to
  // the parent `stvd tetrahedralize` alone, which must pass it on.
  RunningTool tool({"tetrahedralize", in("box.off"), "-o", out("box"), "--max-volume", "0.000005"}, path("capture"));
  std::this_thread::sleep_for(500ms);
  tool.signal(SIGTERM);
  const int status = tool.wait();
  ASSERT_TRUE(WIFSIGNALED(status)) << tool.err();
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_EQ(tool.err(), "stvd tetrahedralize: interrupted (SIGTERM)\n");
  // The parent waited for the child: no meshing goes on to write out/box.*.
  for (const auto& process : fs::directory_iterator("/proc")) {
    std::ifstream cmdline(process.path() / "cmdline");
    std::string words((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    EXPECT_EQ(words.find(out("box")), std::string::npos) << "still running: " << process.path();
  }
  EXPECT_TRUE(listFolder(path("out")).empty());
}

}  // namespace
}  // namespace stvd::testing

// Ctrl-C (SIGINT), SIGTERM (a job scheduler's stop) and SIGHUP end the tool
// by the same signal - shells report 130, 143 and 129 - after it has
// removed whatever it had staged and stopped the processes it runs: a run
// cut short leaves no output and no temporary file, the files that were at
// its output paths stay as they were, and no child process goes on to
// write anything after the tool has said "interrupted". The signals are
// real, sent to real runs, at moments the tests observe (a process has
// taken charge of the signal, a file has been committed, a child has the
// signal pending), never after a guessed delay: they hold on a loaded
// machine.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include "small_inputs.hpp"

extern char** environ;

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// ---------------------------------------------------------------------------
// What /proc says about a process (Linux).

/// A line of /proc/PID/status ("SigBlk", "ShdPnd", ...) without its name;
/// "" when the process is gone.
std::string statusField(pid_t pid, const std::string& name) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(name + ":", 0) == 0) return line.substr(name.size() + 1);
  return "";
}

/// Whether the signal set `field` of the process (SigBlk, SigCgt, SigPnd,
/// ShdPnd) holds `signal`.
bool signalIn(pid_t pid, const std::string& field, int signal) {
  const std::string mask = statusField(pid, field);
  return !mask.empty() && ((std::stoull(mask, nullptr, 16) >> (signal - 1)) & 1u) != 0;
}

/// The tool and stvd-tetrahedralize have taken charge of the termination
/// signals once their thread that waits for them shows
/// (files/termination_signals.hpp). A blocked SIGTERM alone says nothing:
/// glibc blocks every signal for a moment whenever a thread is created,
/// and libraries create threads before main().
bool hasSignalThread(pid_t pid) {
  std::error_code ec;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    std::ifstream comm(task.path() / "comm");
    std::string name;
    if (std::getline(comm, name) && name == "stvd-signals") return true;
  }
  return false;
}

/// The signal is pending for the process (a stopped one keeps it so).
bool pending(pid_t pid, int signal) { return signalIn(pid, "ShdPnd", signal) || signalIn(pid, "SigPnd", signal); }

/// Its state letter (R, S, T, Z, ...), or 0 when it is gone.
char processState(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const std::size_t close = text.rfind(')');
  return close == std::string::npos || close + 2 >= text.size() ? 0 : text[close + 2];
}

/// Alive: neither gone nor a zombie.
bool alive(pid_t pid) {
  const char state = processState(pid);
  return state != 0 && state != 'Z' && state != 'X';
}

/// The command line of a process, its words joined by spaces.
std::string commandLine(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline");
  std::string words((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (char& c : words)
    if (c == '\0') c = ' ';
  return words;
}

/// The live children of a process whose command line holds `word`.
std::vector<pid_t> childrenOf(pid_t parent, const std::string& word = "") {
  std::vector<pid_t> children;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = std::stoi(name);
    std::istringstream status(statusField(pid, "PPid"));
    pid_t ppid = 0;
    if (status >> ppid && ppid == parent && alive(pid) && commandLine(pid).find(word) != std::string::npos)
      children.push_back(pid);
  }
  return children;
}

/// Polls until `condition` holds; fails the test (`what` did not happen)
/// after a bound sized for a loaded machine (a hang, not a slow run).
void waitFor(const std::function<bool()>& condition, const std::string& what) {
  const auto deadline = std::chrono::steady_clock::now() + 240s;
  while (!condition()) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "waited in vain for " << what;
    std::this_thread::sleep_for(1ms);
  }
}

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
  pid_t pid() const { return pid_; }
  /// The wait status once it has ended.
  int wait() {
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    ended_ = true;
    return status;
  }
  /// Not ended (an ended run is not reaped here: wait() gives its status).
  bool running() const {
    siginfo_t info{};
    return waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == 0;
  }
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

  /// What the staging folders in out/ show of a run's outputs.
  struct Staging {
    bool outputStaged = false;  // a folder holds an output's file (not only the run's record)
    bool commitBegun = false;   // a folder holds .previous: the commit keeps the files it replaces
  };
  Staging staging() const {
    Staging seen;
    std::error_code ec;
    for (const auto& folder : fs::directory_iterator(path("out"), ec)) {
      if (folder.path().filename().string().rfind(".stvd-staging-", 0) != 0) continue;
      for (const auto& entry : fs::directory_iterator(folder.path(), ec)) {
        const std::string name = entry.path().filename().string();
        if (name == ".previous") seen.commitBegun = true;
        else if (name != ".stvd-staging-owner") seen.outputStaged = true;
      }
    }
    return seen;
  }
};

TEST_F(ToolInterruption, SigtermDuringTheComputationEndsTheRunAsTheShellSees143) {
  // Lanthier's method with M = 2 takes about 3 s of CPU on the brain. The
  // signal is sent by a bash script, as a job scheduler would send it, as
  // soon as the tool has taken charge of SIGTERM (its thread that waits for
  // the signals shows), which it does first thing in main(); a fixed delay
  // instead races the tool's start, which on a loaded machine takes longer
  // than any delay chosen.
  const std::string script =
      "\"$0\" \"$@\" & pid=$!\n"
      "ready() { local task name; for task in /proc/$1/task/*/comm; do\n"
      "  read -r name < \"$task\" && [[ $name == stvd-signals ]] && return 0; done 2>/dev/null; return 1; }\n"
      "until ready $pid; do kill -0 $pid 2>/dev/null || break; done\n"
      "kill -TERM $pid; wait $pid; echo \"status $?\"";
  const ToolRun run = runToolInBash(script, {"distance", brain, "--seed-voxel", "55,54,15", "--method", "lanthier",
                                             "--steiner", "2", "-o", out("d.nii.gz"), "--stats", out("d.json")});
  EXPECT_EQ(run.out, "status 143\n") << run.err;
  EXPECT_EQ(run.err, "stvd: interrupted (SIGTERM)\n");
  EXPECT_TRUE(listFolder(path("out")).empty());
}

TEST_F(ToolInterruption, SigintWhileWritingRemovesTheStagedOutputsAndKeepsTheEarlierOnes) {
  const std::vector<std::string> arguments{"distance", brain, "--seed-voxel", "55,54,15", "-o", out("d.nii.gz"),
                                           "--stats", out("d.json"), "-q"};
  ASSERT_EQ(runTool(arguments).exitCode, 0);
  // The run is stopped (SIGSTOP) as soon as it has staged an output, and
  // once it is stopped, sent SIGINT and let go on, provided its commit has
  // not begun: a commit keeps the files it will replace (.previous) before
  // it looks for a signal and renames, so without .previous the signal is
  // seen before anything is moved. Should the run have finished or begun
  // its commit by the time it is stopped, it is let finish and the attempt
  // repeated over its outputs.
  for (int attempt = 0; attempt < 5; ++attempt) {
    for (const auto& entry : fs::directory_iterator(path("out")))
      std::ofstream(entry.path(), std::ios::app) << "\nan earlier output\n";
    const FolderSnapshot before = snapshot(path("out"));
    RunningTool tool(arguments, path("capture"));
    while (!staging().outputStaged && tool.running()) {
    }
    tool.signal(SIGSTOP);
    siginfo_t stopped{};  // every thread stopped, or the run ended
    while (waitid(P_PID, static_cast<id_t>(tool.pid()), &stopped, WSTOPPED | WEXITED | WNOWAIT) != 0 && errno == EINTR) {
    }
    const Staging seen = staging();
    if (stopped.si_code != CLD_STOPPED || !seen.outputStaged || seen.commitBegun) {
      tool.signal(SIGCONT);
      ASSERT_EQ(tool.wait(), 0) << tool.err();
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
  // the parent `stvd tetrahedralize` alone, which must pass it on, wait for
  // the child and report it. Sent once the child runs and has taken charge
  // of SIGTERM (before, the signal would end it silently).
  RunningTool tool({"tetrahedralize", in("box.off"), "-o", out("box"), "--max-volume", "0.000005"}, path("capture"));
  pid_t child = 0;
  waitFor(
      [&] {
        for (const pid_t c : childrenOf(tool.pid(), "stvd-tetrahedralize"))
          if (hasSignalThread(c)) child = c;
        return child != 0 || !tool.running();
      },
      "the meshing child to start");
  ASSERT_NE(child, 0) << "the tool ended first: " << tool.err();
  tool.signal(SIGTERM);
  const int status = tool.wait();
  ASSERT_TRUE(WIFSIGNALED(status)) << tool.err();
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_EQ(tool.err(), "stvd tetrahedralize: interrupted (SIGTERM)\n");
  // The parent waited for the child: no meshing goes on to write out/box.*.
  EXPECT_FALSE(alive(child));
  for (const auto& process : fs::directory_iterator("/proc")) {
    std::ifstream cmdline(process.path() / "cmdline");
    std::string words((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    EXPECT_EQ(words.find(out("box")), std::string::npos) << "still running: " << process.path();
  }
  EXPECT_TRUE(listFolder(path("out")).empty());
}

/// `stvd distance --report` on the brain: the map is committed first, then
/// the Python child (stvd.report, which started while the tool computed)
/// draws the page. Runs it until the map is there and the tool's commit is
/// over (its staging folder, which it removes after the rename, gone too),
/// and stops (SIGSTOP) the child, which is then drawing; returns the child's
/// id, or 0 when the run ended before that could be done (the page drawn
/// already).
pid_t stopReportChildOnceTheMapIsCommitted(RunningTool& tool, const std::string& map) {
  pid_t child = 0;
  const std::string toolStaging = ".stvd-staging-" + std::to_string(tool.pid()) + "-";
  const auto committed = [&] {
    if (!fs::exists(map)) return false;
    for (const auto& entry : fs::directory_iterator(fs::path(map).parent_path()))
      if (entry.path().filename().string().rfind(toolStaging, 0) == 0) return false;
    return true;
  };
  waitFor([&] { return committed() || !tool.running(); }, "the distance map");
  for (const pid_t c : childrenOf(tool.pid(), "stvd.report")) {
    ::kill(c, SIGSTOP);
    child = c;
  }
  if (child != 0) waitFor([&] { return processState(child) == 'T' || !alive(child); }, "the child to stop");
  return child;
}

TEST_F(ToolInterruption, SigtermWhileThePageIsDrawnStopsTheReportChildBeforeTheToolEnds) {
  if (!withReports()) GTEST_SKIP() << "built without the Python package, which draws the page";
  const std::vector<std::string> arguments{"distance", brain, "--seed-voxel", "55,54,15", "-o", out("d.nii.gz"),
                                           "--report", out("r.html"), "-q"};
  // Should the page be drawn before the child could be stopped (it takes
  // about a second), the run is repeated.
  for (int attempt = 0; attempt < 5; ++attempt) {
    fs::remove_all(path("out"));
    fs::create_directories(path("out"));
    RunningTool tool(arguments, path("capture"));
    const pid_t child = stopReportChildOnceTheMapIsCommitted(tool, out("d.nii.gz"));
    if (child == 0 || fs::exists(out("r.html"))) {
      tool.wait();
      continue;
    }
    // The child runs with no signal blocked (the tool blocks the three for
    // its own signal thread; a child that inherited them would never see
    // one).
    for (const int s : {SIGINT, SIGTERM, SIGHUP}) EXPECT_FALSE(signalIn(child, "SigBlk", s)) << strsignal(s);
    tool.signal(SIGTERM);
    // Let the child go on once the tool has told it to stop (or has ended
    // without doing so: then the child would draw and write the page).
    waitFor([&] { return pending(child, SIGTERM) || !tool.running(); }, "the tool to pass SIGTERM on");
    ::kill(child, SIGCONT);
    const int status = tool.wait();
    const bool childAliveAfterTheTool = alive(child);
    if (childAliveAfterTheTool) {  // it wrote the page after the tool had reported the interruption
      waitFor([&] { return !alive(child); }, "the orphaned child to end");
    }
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit code " << WEXITSTATUS(status) << ": " << tool.err();
    EXPECT_EQ(WTERMSIG(status), SIGTERM);
    EXPECT_EQ(tool.err(), "stvd: interrupted (SIGTERM)\n");
    EXPECT_FALSE(childAliveAfterTheTool) << "the report child outlived the tool";
    // The map was committed before the signal; the page never is, and
    // nothing staged stays.
    EXPECT_EQ(listFolder(path("out")), std::vector<std::string>{"d.nii.gz"});
    return;
  }
  FAIL() << "the page was drawn every time before the child could be stopped";
}

TEST_F(ToolInterruption, AReportChildDiesWithAToolThatIsKilled) {
  if (!withReports()) GTEST_SKIP() << "built without the Python package, which draws the page";
  // SIGKILL leaves the tool no chance to stop its child: the kernel does
  // (PR_SET_PDEATHSIG), and the child removes what it staged.
  const std::vector<std::string> arguments{"distance", brain, "--seed-voxel", "55,54,15", "-o", out("d.nii.gz"),
                                           "--report", out("r.html"), "-q"};
  for (int attempt = 0; attempt < 5; ++attempt) {
    fs::remove_all(path("out"));
    fs::create_directories(path("out"));
    RunningTool tool(arguments, path("capture"));
    const pid_t child = stopReportChildOnceTheMapIsCommitted(tool, out("d.nii.gz"));
    if (child == 0 || fs::exists(out("r.html"))) {
      tool.wait();
      continue;
    }
    tool.signal(SIGKILL);
    const int status = tool.wait();
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    ::kill(child, SIGCONT);
    waitFor([&] { return !alive(child); }, "the report child to end");
    EXPECT_EQ(listFolder(path("out")), std::vector<std::string>{"d.nii.gz"}) << "the orphaned child wrote on";
    return;
  }
  FAIL() << "the page was drawn every time before the child could be stopped";
}

}  // namespace
}  // namespace stvd::testing

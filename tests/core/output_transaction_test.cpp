// stvd/system/files/output_transaction.hpp: the outputs of a run appear together,
// complete, or not at all, and what was at their paths before stays until
// then.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <sys/stat.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "stvd/system/files/output_transaction.hpp"

namespace stvd::files {
namespace {

namespace fs = std::filesystem;

class OutputTransactionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("stvd_transaction_" + std::to_string(::getpid()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  static std::string contents(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static OutputTransaction::Writer text(const std::string& words) {
    return [words](const std::string& p) {
      std::ofstream out(p, std::ios::binary);
      out << words;
      if (!out.flush()) throw std::runtime_error(p + ": cannot write");
    };
  }

  fs::path folder_;
};

TEST_F(OutputTransactionTest, OutputsAppearOnlyAtTheCommitAndTogether) {
  std::ofstream(path("a.txt")) << "previous a";
  OutputTransaction outputs;
  outputs.write(path("a.txt"), text("new a"));
  outputs.write(path("b.txt"), text("new b"));
  EXPECT_EQ(contents(path("a.txt")), "previous a");
  EXPECT_FALSE(fs::exists(path("b.txt")));
  outputs.commit();
  EXPECT_EQ(contents(path("a.txt")), "new a");
  EXPECT_EQ(contents(path("b.txt")), "new b");
  EXPECT_EQ(entries(), (std::vector<std::string>{"a.txt", "b.txt"})) << "a staging folder was left";
}

TEST_F(OutputTransactionTest, WithoutACommitNothingAppearsAndNothingIsReplaced) {
  std::ofstream(path("a.txt")) << "previous a";
  {
    OutputTransaction outputs;
    outputs.write(path("a.txt"), text("new a"));
    outputs.write(path("b.txt"), text("new b"));
  }
  EXPECT_EQ(contents(path("a.txt")), "previous a");
  EXPECT_EQ(entries(), std::vector<std::string>{"a.txt"});
}

TEST_F(OutputTransactionTest, AFailingWriterIsAnOutputErrorNamingTheFinalPath) {
  OutputTransaction outputs;
  outputs.write(path("a.txt"), text("new a"));
  try {
    outputs.write(path("b.txt"), [](const std::string& p) {
      std::ofstream(p) << "half";
      throw std::runtime_error(p + ": wrote only 4 of 10 bytes");
    });
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path("b.txt") + ": wrote only 4 of 10 bytes");
    EXPECT_EQ(e.path(), path("b.txt"));
  }
}

TEST_F(OutputTransactionTest, LogicErrorsOfAWriterPassUnchanged) {
  OutputTransaction outputs;
  EXPECT_THROW(outputs.write(path("a.txt"), [](const std::string&) { throw std::invalid_argument("a bug"); }),
               std::invalid_argument);
}

TEST_F(OutputTransactionTest, AWriterThatWritesNothingFails) {
  OutputTransaction outputs;
  EXPECT_THROW(outputs.write(path("a.txt"), [](const std::string&) {}), OutputError);
}

TEST_F(OutputTransactionTest, CompanionFilesMoveWithTheirOutput) {
  OutputTransaction outputs;
  outputs.write(path("d.nhdr"), [](const std::string& p) {
    std::ofstream(p) << "NRRD0004\ndata file: d.raw.gz\n";
    std::ofstream(fs::path(p).parent_path() / "d.raw.gz") << "data";
  });
  EXPECT_FALSE(fs::exists(path("d.raw.gz")));
  outputs.commit();
  EXPECT_EQ(contents(path("d.raw.gz")), "data");
  EXPECT_EQ(entries(), (std::vector<std::string>{"d.nhdr", "d.raw.gz"}));
}

TEST_F(OutputTransactionTest, WhenARenameFailsTheOutputsAlreadyMovedAreUndone) {
  std::ofstream(path("a.txt")) << "previous a";
  OutputTransaction outputs;
  outputs.write(path("a.txt"), text("new a"));
  outputs.write(path("b.txt"), text("new b"));
  // b.txt becomes a non-empty folder after it was checked: its rename fails.
  fs::create_directories(path("b.txt/inside"));
  EXPECT_THROW(outputs.commit(), OutputError);
  EXPECT_EQ(contents(path("a.txt")), "previous a") << "the replaced file was not restored";
  EXPECT_TRUE(fs::is_directory(path("b.txt/inside")));
}

TEST_F(OutputTransactionTest, TheSameFileTwiceInOneRunIsAnError) {
  OutputTransaction outputs;
  outputs.write(path("a.txt"), text("one"));
  EXPECT_THROW(outputs.write(folder_.string() + "/./a.txt", text("two")), OutputError);
}

TEST_F(OutputTransactionTest, UnusableOutputPathsAreFoundBeforeAnyWork) {
  EXPECT_THROW(checkOutputPath(path("missing/d.nii")), OutputError);
  EXPECT_THROW(checkOutputPath(folder_.string()), OutputError);
  EXPECT_THROW(checkOutputPath(""), OutputError);
  EXPECT_NO_THROW(checkOutputPath(path("d.nii")));
  EXPECT_THROW(writeAtomically(path("missing/d.txt"), text("x")), OutputError);
  EXPECT_TRUE(entries().empty());
}

TEST_F(OutputTransactionTest, WriteAtomicallyIsOneTransaction) {
  writeAtomically(path("a.txt"), text("alone"));
  EXPECT_EQ(contents(path("a.txt")), "alone");
  EXPECT_EQ(entries(), std::vector<std::string>{"a.txt"});
}

/// A child process that stages `name` in `folder` and then stops: killed
/// with SIGKILL (no cleanup) when `die`, otherwise waiting until its
/// parent kills it. Returns its pid once the staged file exists.
pid_t stagingChild(const std::string& folder, const std::string& name, bool die) {
  int ready[2];
  if (::pipe(ready) != 0) return -1;
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(ready[0]);
    OutputTransaction outputs;
    outputs.write(folder + "/" + name, [&](const std::string& staging) {
      std::ofstream(staging) << "half";
      if (die) ::kill(::getpid(), SIGKILL);
      (void)!::write(ready[1], "r", 1);
      ::pause();
    });
    ::_exit(0);  // not reached
  }
  ::close(ready[1]);
  char c;
  (void)!::read(ready[0], &c, 1);  // staged (or dead)
  ::close(ready[0]);
  return child;
}

TEST_F(OutputTransactionTest, LeftoverStagingFoldersOfAKilledRunAreRemovedAndLiveOnesKept) {
  // A child process that writes an output and goes on living, and one
  // killed (SIGKILL, no cleanup) while it writes (each sweeps the folder
  // before it stages: the live one first, so that the dead one's is there).
  const pid_t live = stagingChild(folder_.string(), "c.txt", false);
  struct Reap {  // the live child never outlives the test, whatever fails
    pid_t pid;
    ~Reap() {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  } reap{live};
  const pid_t dead = stagingChild(folder_.string(), "a.txt", true);
  int status = 0;
  ASSERT_EQ(::waitpid(dead, &status, 0), dead);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  auto folderOf = [this](pid_t pid) {  // its staging folder (the counter is the parent's, copied by fork)
    for (const std::string& name : entries())
      if (name.rfind(kStagingFolderPrefix + std::to_string(pid) + "-", 0) == 0) return name;
    return std::string();
  };
  ASSERT_NE(folderOf(dead), "");
  const std::string liveFolder = folderOf(live);
  ASSERT_NE(liveFolder, "");
  // What is not demonstrably ours: a folder named like ours without the
  // record our runs write, and a file.
  fs::create_directory(path(".stvd-staging-1-1"));
  std::ofstream(path(".stvd-staging-1-1/a.txt")) << "someone's";
  std::ofstream(path(".stvd-staging-notes.txt")) << "a file, not a staging folder";

  EXPECT_EQ(removeLeftoverStagingFolders(folder_.string()), 1u);  // the dead child's
  OutputTransaction ours;
  ours.write(path("b.txt"), text("new b"));
  EXPECT_EQ(removeLeftoverStagingFolders((folder_ / "." / "").string()), 0u);  // this process's, kept
  ours.commit();
  EXPECT_EQ(entries(), (std::vector<std::string>{".stvd-staging-1-1", liveFolder, ".stvd-staging-notes.txt",
                                                 "b.txt"}));
  // Once the live one is killed too (and still a zombie, not reaped), its
  // folder goes as well, the next time a run stages here.
  ::kill(live, SIGKILL);
  siginfo_t info{};
  ASSERT_EQ(::waitid(P_PID, static_cast<id_t>(live), &info, WEXITED | WNOWAIT), 0);
  EXPECT_EQ(removeLeftoverStagingFolders(folder_.string()), 1u);
  EXPECT_EQ(contents(path(".stvd-staging-1-1/a.txt")), "someone's");
}

TEST_F(OutputTransactionTest, TheFirstOutputStagedInAFolderRemovesTheLeftoversThere) {
  const pid_t dead = stagingChild(folder_.string(), "a.txt", true);
  ::waitpid(dead, nullptr, 0);
  ASSERT_EQ(entries().size(), 1u);
  writeAtomically(path("b.txt"), text("b"));
  EXPECT_EQ(entries(), std::vector<std::string>{"b.txt"});
}

TEST_F(OutputTransactionTest, AReplacedFileKeepsItsMode) {
  std::ofstream(path("a.txt")) << "previous";
  ASSERT_EQ(::chmod(path("a.txt").c_str(), 0640), 0);
  writeAtomically(path("a.txt"), text("new"));
  struct stat status {};
  ASSERT_EQ(::stat(path("a.txt").c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 07777, 0640u);
  EXPECT_EQ(contents(path("a.txt")), "new");
}

TEST_F(OutputTransactionTest, AFifoIsWrittenToAndStaysAFifo) {
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0644), 0);
  std::string got;
  std::thread reader([&] { got = contents(path("f")); });
  OutputTransaction outputs;
  outputs.write(path("f"), text("streamed"));
  outputs.write(path("b.txt"), text("b"));
  outputs.commit();
  reader.join();
  EXPECT_EQ(got, "streamed");
  struct stat status {};
  ASSERT_EQ(::lstat(path("f").c_str(), &status), 0);
  EXPECT_TRUE(S_ISFIFO(status.st_mode));
  EXPECT_EQ(entries(), (std::vector<std::string>{"b.txt", "f"}));
}

TEST_F(OutputTransactionTest, AStreamWhoseReaderIsGoneLeavesTheFilesAsTheyWere) {
  ASSERT_EQ(::mkfifo(path("f").c_str(), 0644), 0);
  std::ofstream(path("b.txt")) << "previous b";
  // The reader opens the FIFO and closes it at once: the write fails with
  // EPIPE (and SIGPIPE does not end the process).
  std::thread reader([&] { std::ifstream(path("f")).close(); });
  OutputTransaction outputs;
  outputs.write(path("f"), text(std::string(1 << 20, 'x')));
  outputs.write(path("b.txt"), text("new b"));
  try {
    outputs.commit();
    ADD_FAILURE() << "the commit succeeded";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()).find(path("f") + ": cannot write to a FIFO: Broken pipe"), 0u) << e.what();
  }
  reader.join();
  EXPECT_EQ(contents(path("b.txt")), "previous b");
}

}  // namespace
}  // namespace stvd::files

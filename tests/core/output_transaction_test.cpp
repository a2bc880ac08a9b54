// stvd/files/output_transaction.hpp: the outputs of a run appear together,
// complete, or not at all, and what was at their paths before stays until
// then.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

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

TEST_F(OutputTransactionTest, LeftoverStagingFoldersOfAKilledRunAreRemovedAndLiveOnesKept) {
  // A child process killed (SIGKILL, no cleanup) while it writes an output.
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    OutputTransaction outputs;
    outputs.write(path("a.txt"), [](const std::string& staging) {
      std::ofstream(staging) << "half";
      ::kill(::getpid(), SIGKILL);
    });
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  ASSERT_EQ(entries().size(), 1u);
  ASSERT_EQ(entries()[0].rfind(kStagingFolderPrefix + std::to_string(child) + "-", 0), 0u) << entries()[0];

  std::ofstream(path(".stvd-staging-notes.txt")) << "a file, not a staging folder";
  OutputTransaction live;
  live.write(path("b.txt"), text("new b"));
  EXPECT_EQ(removeLeftoverStagingFolders(folder_.string()), 1u);
  EXPECT_EQ(removeLeftoverStagingFolders((folder_ / "." / "").string()), 0u);  // this process's, kept
  live.commit();
  EXPECT_EQ(entries(), (std::vector<std::string>{".stvd-staging-notes.txt", "b.txt"}));
}

}  // namespace
}  // namespace stvd::files

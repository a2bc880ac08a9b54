// stvd/system/files/file_identity.hpp: an output is compared with the inputs by
// what file it is, not by how it is spelled.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "stvd/system/files/file_identity.hpp"

namespace stvd::files {
namespace {

namespace fs = std::filesystem;

class FileIdentity : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("stvd_identity_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "data");
    fs::create_directories(root_ / "out");
    std::ofstream(path("data/t.nii.gz")) << "tensors";
    previous_ = fs::current_path();
    fs::current_path(root_ / "out");  // relative spellings start here
  }
  void TearDown() override {
    fs::current_path(previous_);
    fs::remove_all(root_);
  }
  std::string path(const std::string& relative) const { return (root_ / relative).string(); }

  fs::path root_, previous_;
};

TEST_F(FileIdentity, AnExistingFileIsItselfHoweverItIsSpelled) {
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), "../data/t.nii.gz"));
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), "./../data/./t.nii.gz"));
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), path("out/../data/t.nii.gz")));
}

TEST_F(FileIdentity, SymbolicAndHardLinksAreTheFileTheyLeadTo) {
  fs::create_symlink(path("data/t.nii.gz"), path("out/link.nii.gz"));
  fs::create_hard_link(path("data/t.nii.gz"), path("out/hard.nii.gz"));
  fs::create_directory_symlink(path("data"), path("out/linked_data"));
  EXPECT_TRUE(sameFile("link.nii.gz", path("data/t.nii.gz")));
  EXPECT_TRUE(sameFile("hard.nii.gz", path("data/t.nii.gz")));
  EXPECT_TRUE(sameFile("linked_data/t.nii.gz", path("data/t.nii.gz")));
}

TEST_F(FileIdentity, NewFilesAreComparedByTheirCanonicalPath) {
  fs::create_directory_symlink(path("data"), path("out/linked_data"));
  EXPECT_TRUE(sameFile("new.nii", path("out/new.nii")));
  EXPECT_TRUE(sameFile("linked_data/new.nii", path("data/new.nii")));
  EXPECT_TRUE(sameFile("../out/./new.nii", "new.nii"));
  EXPECT_FALSE(sameFile("new.nii", "other.nii"));
  EXPECT_FALSE(sameFile("new.nii", path("data/t.nii.gz")));
}

TEST_F(FileIdentity, AnOutputThatIsAnInputIsAConflictNamingBothRoles) {
  const std::vector<RunFile> inputs{{"tensor input", path("data/t.nii.gz")}, {"mask", path("data/mask.nii.gz")}};
  try {
    checkOutputsAreNotInputs(inputs, {{"distance map", "../data/t.nii.gz"}});
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_EQ(std::string(e.what()), "../data/t.nii.gz: the distance map is the tensor input (" +
                                         path("data/t.nii.gz") +
                                         ", the same file); stvd never writes over an input, choose another "
                                         "output file");
  }
  // A mask that does not exist yet is still an input the output must not be.
  EXPECT_THROW(checkOutputsAreNotInputs(inputs, {{"distance map", path("data/mask.nii.gz")}}), FileConflict);
  EXPECT_NO_THROW(checkOutputsAreNotInputs(inputs, {{"distance map", "d.nii.gz"}, {"statistics file", "s.json"}}));
}

TEST_F(FileIdentity, TwoOutputsThatAreOneFileAreAConflict) {
  try {
    checkOutputsAreNotInputs({}, {{"distance map", "d.nii.gz"}, {"statistics file", "./d.nii.gz"}});
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_NE(std::string(e.what()).find("./d.nii.gz: the statistics file is the distance map"), std::string::npos)
        << e.what();
  }
}

TEST_F(FileIdentity, AnInputMayBeGivenInSeveralRoles) {
  EXPECT_NO_THROW(checkOutputsAreNotInputs(
      {{"mask", path("data/t.nii.gz")}, {"seed labels", "../data/t.nii.gz"}}, {{"distance map", "d.nii.gz"}}));
}

TEST_F(FileIdentity, AmongManyFilesTheFirstConflictInOrderIsNamed) {
  // A cohort's check: thousands of inputs and outputs, most not existing
  // yet. The conflict named is the first the pairwise comparison in order
  // meets: the earliest input the output is, by inode or by path.
  fs::create_symlink(path("data/t.nii.gz"), path("data/link.nii.gz"));
  std::vector<RunFile> inputs, outputs;
  for (int n = 0; n < 5000; ++n) {
    inputs.push_back({"labels of subject " + std::to_string(n), path("in/" + std::to_string(n) + ".nii.gz")});
    outputs.push_back({"table of subject " + std::to_string(n), path("out/" + std::to_string(n) + ".tsv")});
  }
  inputs[4700] = {"tensors of subject 4700", path("data/t.nii.gz")};
  inputs[3200] = {"tensors of subject 3200", path("data/link.nii.gz")};
  EXPECT_NO_THROW(checkOutputsAreNotInputs(inputs, outputs));

  outputs.push_back({"table of subject x", "../data/t.nii.gz"});
  try {
    checkOutputsAreNotInputs(inputs, outputs);
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_NE(std::string(e.what()).find("the table of subject x is the tensors of subject 3200"), std::string::npos)
        << e.what();
  }
  outputs.back() = {"table of subject x", path("in/900.nii.gz")};  // no file yet: by its path
  try {
    checkOutputsAreNotInputs(inputs, outputs);
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_NE(std::string(e.what()).find("the table of subject x is the labels of subject 900"), std::string::npos)
        << e.what();
  }
  outputs.back() = {"table of subject x", "./800.tsv"};  // another output
  EXPECT_THROW(checkOutputsAreNotInputs(inputs, outputs), FileConflict);
}

}  // namespace
}  // namespace stvd::files

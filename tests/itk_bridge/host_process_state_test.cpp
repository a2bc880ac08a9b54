// A library leaves its host's process as it found it. After every call of
// the ITK file I/O, made from two threads at once, ITK's output window is
// still the one the host installed and file descriptor 2 is still the
// host's file; ITK's messages are not swallowed (they reach the host's
// window, or our errors). Only a program that owns its process
// (installItkMessageFilter, the `stvd` tool) keeps ITK's messages off the
// terminal, and then only those given during our calls.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <itkOutputWindow.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "stvd/itk.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

/// The host's own ITK output window: it records what it is given.
class RecordingWindow : public itk::OutputWindow {
 public:
  ITK_DISALLOW_COPY_AND_MOVE(RecordingWindow);
  using Self = RecordingWindow;
  using Pointer = itk::SmartPointer<Self>;
  static Pointer New() {
    Pointer p = new Self;
    p->UnRegister();
    return p;
  }
  void DisplayText(const char* text) override {
    std::lock_guard<std::mutex> guard(lock_);
    texts_.emplace_back(text);
  }
  std::vector<std::string> texts() const {
    std::lock_guard<std::mutex> guard(lock_);
    return texts_;
  }

 protected:
  RecordingWindow() = default;

 private:
  mutable std::mutex lock_;
  std::vector<std::string> texts_;
};

struct FileIdentity {
  dev_t device = 0;
  ino_t inode = 0;
  int flags = 0;
  bool operator==(const FileIdentity& o) const {
    return device == o.device && inode == o.inode && flags == o.flags;
  }
};

FileIdentity identityOf(int fd) {
  struct stat s {};
  if (::fstat(fd, &s) != 0) return {};
  return {s.st_dev, s.st_ino, ::fcntl(fd, F_GETFL)};
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class HostProcessState : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    previousWindow_ = itk::OutputWindow::GetInstance();
    host_ = RecordingWindow::New();
    itk::OutputWindow::SetInstance(host_);
    // The host's standard error is a file of its own.
    std::fflush(stderr);
    savedFd2_ = ::dup(2);
    hostStderr_ = ::open(path("host_stderr.txt").c_str(), O_CREAT | O_WRONLY | O_TRUNC | O_APPEND, 0600);
    ASSERT_GE(hostStderr_, 0);
    ASSERT_GE(::dup2(hostStderr_, 2), 0);
    fd2_ = identityOf(2);

    geometry_.size = {5, 4, 3};
    geometry_.spacing = {1.5, 2, 2.5};
    std::vector<std::array<float, 6>> tensors(60, {1, 0, 1, 0, 0, 1});
    writeNiftiByHand(path("tensors.nii"), geometry_, NiftiTensorLayout::SymMatrix5D, tensors);
    std::string bytes = slurp(path("tensors.nii"));
    std::string analyze = bytes;
    std::memset(analyze.data() + 344, 0, 4);  // no NIfTI magic: ITK warns on its output window
    std::ofstream(path("analyze.nii"), std::ios::binary) << analyze;
    std::ofstream(path("truncated.nii"), std::ios::binary) << bytes.substr(0, bytes.size() - 100);
  }
  void TearDown() override {
    std::fflush(stderr);
    ::dup2(savedFd2_, 2);
    ::close(savedFd2_);
    ::close(hostStderr_);
    itk::OutputWindow::SetInstance(previousWindow_);
    ScratchFolderTest::TearDown();
  }

  /// Runs `call`, then checks that the host's window and fd 2 are in place.
  void expectHostStateAfter(const char* what, const std::function<void()>& call) {
    call();
    EXPECT_EQ(itk::OutputWindow::GetInstance().GetPointer(), host_.GetPointer()) << "after " << what;
    EXPECT_TRUE(identityOf(2) == fd2_) << "file descriptor 2 changed after " << what;
  }

  /// Every kind of adapter call, `repeats` times: reads, a write, a header
  /// ITK warns about, a truncated file.
  void callTheAdapter(int thread, int repeats) {
    for (int r = 0; r < repeats; ++r) {
      expectHostStateAfter("readTensorVolume", [&] {
        EXPECT_EQ(imaging::readTensorVolume(path("tensors.nii")).volume.tensors.size(), 60u);
      });
      expectHostStateAfter("readImageGrid of an Analyze header", [&] {
        std::vector<std::string> warnings;
        imaging::readImageGrid(path("analyze.nii"), &warnings);
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_NE(warnings[0].find("Analyze 7.5"), std::string::npos) << warnings[0];
      });
      expectHostStateAfter("readTensorVolume of a truncated file", [&] {
        try {
          imaging::readTensorVolume(path("truncated.nii"));
          ADD_FAILURE() << "a truncated file was read";
        } catch (const imaging::ImageIoError& e) {
          // ITK's own diagnosis is part of our one line.
          const std::string said = e.what();
          EXPECT_EQ(said.rfind(path("truncated.nii") + ": ", 0), 0u) << said;
          EXPECT_GT(said.size(), path("truncated.nii").size() + 30) << said;
        }
      });
      const std::string out = path("d" + std::to_string(thread) + "_" + std::to_string(r) + ".nii.gz");
      const std::vector<float> values(60, static_cast<float>(thread + r));
      expectHostStateAfter("writeScalarImage", [&] { imaging::writeScalarImage(out, geometry_.grid(), values); });
      expectHostStateAfter("readScalarImage", [&] { EXPECT_EQ(imaging::readScalarImage(out).values, values); });
    }
  }

  itk::OutputWindow::Pointer previousWindow_;
  RecordingWindow::Pointer host_;
  int savedFd2_ = -1, hostStderr_ = -1;
  FileIdentity fd2_;
  HandGeometry geometry_;
};

TEST_F(HostProcessState, TheHostsOutputWindowAndStandardErrorStayAfterEveryCallFromTwoThreads) {
  std::thread other([&] { callTheAdapter(1, 8); });
  callTheAdapter(0, 8);
  other.join();
  // Nothing was swallowed: ITK's warning about each Analyze header went
  // where the host sends ITK's output, as for any ITK call of its own.
  int analyzeWarnings = 0;
  for (const std::string& t : host_->texts()) analyzeWarnings += t.find("WARNING") != std::string::npos;
  EXPECT_EQ(analyzeWarnings, 16);
}

TEST_F(HostProcessState, TheToolsFilterKeepsOnlyOurCallsMessagesOffTheTerminal) {
  // What a program that owns its process does once at start-up.
  imaging::installItkMessageFilter();
  const itk::OutputWindow* filter = itk::OutputWindow::GetInstance().GetPointer();
  EXPECT_NE(filter, host_.GetPointer());
  std::atomic<bool> done{false};
  std::thread reader([&] {
    for (int r = 0; r < 8; ++r) imaging::readImageGrid(path("analyze.nii"));
    done = true;
  });
  // Meanwhile the host's own messages, on another thread, reach its window.
  int own = 0;
  while (!done || own < 3) itk::OutputWindowDisplayText(("the host's message " + std::to_string(own++)).c_str());
  reader.join();
  const std::vector<std::string> texts = host_->texts();
  ASSERT_EQ(texts.size(), static_cast<std::size_t>(own));
  for (int i = 0; i < own; ++i) EXPECT_EQ(texts[i], "the host's message " + std::to_string(i));
  EXPECT_EQ(itk::OutputWindow::GetInstance().GetPointer(), filter);
  EXPECT_TRUE(identityOf(2) == fd2_);
}

}  // namespace
}  // namespace stvd::testing

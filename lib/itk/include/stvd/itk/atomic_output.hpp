// Writing output files so that they appear complete or not at all.
#pragma once

#include <string>

namespace stvd::imaging {

/// Throws ImageIoError naming `path` when it cannot become an output file:
/// its folder does not exist, is not a folder, or is not writable, or `path`
/// names an existing folder. Lets a tool fail before long work, not after.
void checkOutputPath(const std::string& path);

/// A private staging folder next to the final output. Writers write the
/// output (and any files that go with it, such as the data file of a
/// detached .nhdr header) into stagingPath(); commit() moves them into the
/// output folder by rename, which is atomic within one file system. Without
/// commit(), the destructor removes the staging folder and everything in it,
/// so a failed write leaves nothing behind.
class AtomicOutput {
 public:
  /// Creates the staging folder "<folder>/.stvd-staging-<pid>-<n>".
  /// Throws ImageIoError (see checkOutputPath).
  explicit AtomicOutput(std::string path);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// Where to write: the staging folder plus the output's file name.
  const std::string& stagingPath() const { return stagingPath_; }
  /// Moves every staged file into the output folder (the main file last)
  /// and removes the staging folder. Throws ImageIoError.
  void commit();

 private:
  void removeStaging() noexcept;

  std::string path_;
  std::string folder_;
  std::string stagingFolder_;
  std::string stagingPath_;
  bool committed_ = false;
};

}  // namespace stvd::imaging

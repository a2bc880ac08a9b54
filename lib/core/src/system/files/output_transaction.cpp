#include "stvd/system/files/output_transaction.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <system_error>

#include "process_registry.hpp"
#include "staging_record.hpp"
#include "stvd/system/files/file_identity.hpp"
#include "stvd/system/files/output_destination.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace fs = std::filesystem;

namespace stvd::files {
namespace {

std::string folderOf(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  return folder.empty() ? std::string(".") : folder.string();
}

std::string errnoText() { return std::strerror(errno); }

/// fsync of a file (or, with O_DIRECTORY, a folder); "" or the problem.
std::string flushToDisk(const std::string& path, bool folder) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (folder ? O_DIRECTORY : 0));
  if (fd < 0) return "cannot open " + path + " to flush it: " + errnoText();
  std::string problem;
  // Some file systems cannot sync a folder (EINVAL); that is no data loss.
  if (::fsync(fd) != 0 && !(folder && (errno == EINVAL || errno == EROFS))) problem = errnoText();
  ::close(fd);
  return problem;
}

void replaceAll(std::string& text, const std::string& from, const std::string& to) {
  if (from.empty()) return;
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

/// The staging folders in `folder` whose runs are gone (see
/// staging_record.hpp); with the registry locked.
std::vector<fs::path> abandonedStagingFolders(const std::string& folder, const detail::ProcessRegistry& registry,
                                              std::error_code& ec) {
  const std::string prefix = kStagingFolderPrefix;
  std::vector<fs::path> abandoned;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    // This process's names are unique (its id and a counter): compared by
    // name, however the folder was spelled.
    const auto& ours = registry.stagingFolders;
    if (std::any_of(ours.begin(), ours.end(), [&](const std::string& f) { return fs::path(f).filename() == name; }))
      continue;
    if (detail::isAbandonedStagingFolder(entry.path().string(), name)) abandoned.push_back(entry.path());
  }
  return abandoned;
}

/// Once per folder and process, before the first output is staged there:
/// removes what runs killed before they could clean up left in it. Never a
/// reason to fail the run.
void sweepOnce(const std::string& folder, detail::ProcessRegistry& registry) {
  static std::set<std::string> swept;
  std::error_code ec;
  const std::string key = fs::weakly_canonical(fs::absolute(folder, ec), ec).string();
  if (ec || !swept.insert(key).second) return;
  for (const fs::path& leftover : abandonedStagingFolders(folder, registry, ec)) fs::remove_all(leftover, ec);
}

/// The temporary folder in which the outputs that are streams are staged.
std::string streamStagingParent() {
  std::error_code ec;
  const fs::path temporary = fs::temp_directory_path(ec);
  return ec || temporary.empty() ? std::string("/tmp") : temporary.string();
}

/// Writes `bytes` of the staged file at `from` to the descriptor `to`.
/// Returns an empty string or the problem. SIGPIPE (a reader that went
/// away) is blocked in this thread while it writes and taken back after,
/// so that it becomes the error EPIPE instead of ending the process.
std::string copyToStream(const std::string& from, int to) {
  sigset_t pipeSignal, previous;
  sigemptyset(&pipeSignal);
  sigaddset(&pipeSignal, SIGPIPE);
  ::pthread_sigmask(SIG_BLOCK, &pipeSignal, &previous);
  std::string problem;
  try {
    const RegularFile source(from);
    char buffer[1 << 16];
    for (;;) {
      const ssize_t got = ::read(source.descriptor(), buffer, sizeof buffer);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) {
        problem = std::string("cannot read the staged output: ") + std::strerror(errno);
        break;
      }
      if (got == 0) break;
      std::size_t done = 0;
      while (done < static_cast<std::size_t>(got) && problem.empty()) {
        const ssize_t n = ::write(to, buffer + done, static_cast<std::size_t>(got) - done);
        if (n > 0) {
          done += static_cast<std::size_t>(n);
        } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
          const struct timespec pause { 0, 1000000 };  // a non-blocking descriptor that is full
          ::nanosleep(&pause, nullptr);
        } else if (!(n < 0 && errno == EINTR)) {
          problem = n < 0 ? std::strerror(errno) : "the system wrote nothing";
        }
      }
      if (!problem.empty()) break;
    }
  } catch (const InputFileError& e) {
    problem = e.problem();
  }
  if (!sigismember(&previous, SIGPIPE)) {
    const struct timespec now { 0, 0 };
    while (::sigtimedwait(&pipeSignal, nullptr, &now) == SIGPIPE) {
    }
  }
  ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  return problem;
}

/// The mode bits, group (and, for root, owner) of the file an output
/// replaces, given to the staged file that replaces it: a 0600 file stays
/// 0600. Set-user-ID, set-group-ID and sticky bits are not carried over.
/// Best effort: a group this user may not give is left as it is.
void keepModeAndOwnership(const fs::path& staged, const struct stat& replaced) {
  const int fd = ::open(staged.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  struct stat current {};
  if (::fstat(fd, &current) == 0) {
    const uid_t owner = ::geteuid() == 0 ? replaced.st_uid : static_cast<uid_t>(-1);
    if (replaced.st_gid != current.st_gid || (owner != static_cast<uid_t>(-1) && owner != current.st_uid))
      (void)!::fchown(fd, owner, replaced.st_gid);
    (void)!::fchmod(fd, replaced.st_mode & 0777);
  }
  ::close(fd);
}

}  // namespace

detail::ProcessRegistry& detail::processRegistry() {
  static ProcessRegistry registry;
  return registry;
}

void checkOutputPath(const std::string& path) {
  if (path.empty()) throw OutputError("(output)", "the output path is empty");
  if (fs::path(path).filename().empty()) throw OutputError(path, "the output path names a folder, not a file");
  const OutputDestination destination = outputDestination(path);  // throws for sockets and block devices
  if (destination.isStream()) {
    if (destination.descriptor < 0 && ::access(path.c_str(), W_OK) != 0)
      throw OutputError(path, "cannot write to " + destination.description + ": " + errnoText());
    return;
  }
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw OutputError(path, "the output path is an existing folder");
  const std::string folder = folderOf(path);
  if (!fs::exists(folder, ec)) throw OutputError(path, "the output folder '" + folder + "' does not exist");
  if (!fs::is_directory(folder, ec)) throw OutputError(path, "'" + folder + "' is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw OutputError(path, "the output folder '" + folder + "' is not writable");
}

struct OutputTransaction::Staged {
  std::string path;           // as the caller named it
  std::string folder;         // where it goes
  OutputDestination destination;
  std::string stagingFolder;  // "<folder>/.stvd-staging-<pid>-<n>", registered
  std::string stagingPath;    // stagingFolder + the output's file name

  Staged(std::string output, OutputDestination where)
      : path(std::move(output)), folder(folderOf(path)), destination(std::move(where)) {
    static std::atomic<unsigned> counter{0};
    // A stream is staged in the temporary folder: nothing is ever made
    // next to a device or a FIFO (in /dev, say).
    const std::string parent = destination.isStream() ? streamStagingParent() : folder;
    const std::string name = fs::path(path).filename().string();
    detail::ProcessRegistry& registry = detail::processRegistry();
    const std::lock_guard<std::mutex> lock(registry.mutex);
    sweepOnce(parent, registry);
    for (int attempt = 0; attempt < 100; ++attempt) {
      const fs::path candidate =
          fs::path(parent) / (kStagingFolderPrefix + std::to_string(::getpid()) + "-" + std::to_string(counter++));
      if (::mkdir(candidate.c_str(), 0700) == 0) {
        stagingFolder = candidate.string();
        stagingPath = (candidate / name).string();
        registry.stagingFolders.push_back(stagingFolder);
        // Without its record the folder is never taken for a leftover: it
        // stays if this process is killed, but nothing else is lost.
        (void)detail::writeStagingRecord(stagingFolder);
        return;
      }
      if (errno != EEXIST)
        throw OutputError(path, "cannot create a staging folder in '" + parent + "': " + errnoText());
    }
    throw OutputError(path, "cannot create a staging folder in '" + parent + "'");
  }

  ~Staged() {
    detail::ProcessRegistry& registry = detail::processRegistry();
    const std::lock_guard<std::mutex> lock(registry.mutex);
    std::error_code ec;
    fs::remove_all(stagingFolder, ec);
    auto& folders = registry.stagingFolders;
    folders.erase(std::remove(folders.begin(), folders.end(), stagingFolder), folders.end());
  }

  /// The staged files, companions first and the named file last.
  std::vector<fs::path> files() const {
    std::vector<fs::path> list;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(stagingFolder, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.path() != fs::path(stagingPath) && name != kPrevious && name != detail::kStagingRecordName)
        list.push_back(entry.path());
    }
    if (ec) throw OutputError(path, "cannot list the staging folder: " + ec.message());
    std::sort(list.begin(), list.end());
    list.push_back(stagingPath);
    return list;
  }

  /// Where the files an output replaces are kept until the commit is done.
  static constexpr const char* kPrevious = ".previous";
};

OutputTransaction::OutputTransaction() = default;
OutputTransaction::~OutputTransaction() = default;  // each Staged removes its folder

void OutputTransaction::write(const std::string& path, const Writer& writer) {
  if (committed_) throw std::logic_error("OutputTransaction::write after commit");
  checkOutputPath(path);
  const std::string name = fs::path(path).filename().string();
  if (name == Staged::kPrevious || name == detail::kStagingRecordName)
    throw OutputError(path, "stvd keeps its own files under this name while it writes; choose another file name");
  for (const auto& s : staged_)
    if (sameFile(s->path, path)) throw OutputError(path, "the run writes this file twice (also as " + s->path + ")");
  staged_.push_back(std::make_unique<Staged>(path, outputDestination(path)));
  const Staged& s = *staged_.back();
  // A failed output is removed at once: a later commit() moves only the
  // outputs that were written completely (callers normally give up).
  auto fail = [&](const std::string& problem) {
    staged_.pop_back();
    throw OutputError(path, problem);
  };
  try {
    writer(s.stagingPath);
  } catch (const std::runtime_error& e) {  // OutputError included: it may name the staging path
    std::string message = e.what();
    replaceAll(message, s.stagingPath, path);
    replaceAll(message, s.stagingFolder, s.folder);
    if (message.rfind(path + ": ", 0) == 0) message.erase(0, path.size() + 2);
    fail(message);
  } catch (...) {
    staged_.pop_back();
    throw;
  }
  std::error_code ec;
  if (!fs::is_regular_file(s.stagingPath, ec)) fail("the writer produced no file");
  if (s.destination.isStream()) {  // streamed at the commit; nothing to flush
    if (s.files().size() != 1)
      fail("is " + s.destination.description + ", a stream, which cannot take the other files this format " +
           "writes next to its file; write it to a regular file");
    return;
  }
  for (const fs::path& file : s.files()) {
    const std::string problem = flushToDisk(file.string(), false);
    if (!problem.empty()) fail("cannot write " + file.filename().string() + " to disk: " + problem);
  }
}

void OutputTransaction::commit() {
  if (committed_) throw std::logic_error("OutputTransaction::commit twice");
  struct Move {
    fs::path destination;
    fs::path previous;  // the replaced file, kept here; empty when there was none
  };
  std::vector<Move> done;
  // A file is never renamed over anything but a regular file (or a
  // symbolic link, which is replaced itself): not over a FIFO, a device or
  // a socket that a companion's name happens to name.
  for (const auto& s : staged_) {
    if (s->destination.isStream()) continue;
    for (const fs::path& file : s->files()) {
      const fs::path destination = fs::path(s->folder) / file.filename();
      struct stat status {};
      if (::lstat(destination.c_str(), &status) == 0 && !S_ISREG(status.st_mode) && !S_ISLNK(status.st_mode) &&
          !S_ISDIR(status.st_mode))
        throw OutputError(s->path, destination.string() + " is " + fileKindName(status.st_mode) +
                                       ", which stvd never replaces; nothing was written");
    }
  }
  // Streams first, before any file is moved into place: a stream that
  // cannot be written (a reader gone, /dev/full) leaves every file output
  // as it was. What a stream has taken cannot be taken back. Written
  // without the registry's lock, so that a termination signal is handled
  // while a FIFO waits for its reader.
  for (const auto& s : staged_) {
    if (!s->destination.isStream()) continue;
    int fd = s->destination.descriptor;
    const bool opened = fd < 0;
    if (opened) {
      do {
        fd = ::open(s->path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
      } while (fd < 0 && errno == EINTR);
      if (fd < 0) throw OutputError(s->path, "cannot open " + s->destination.description + ": " + errnoText());
      struct stat status {};
      if (::fstat(fd, &status) != 0 || !(S_ISCHR(status.st_mode) || S_ISFIFO(status.st_mode))) {
        ::close(fd);
        throw OutputError(s->path, "is no longer " + s->destination.description + "; nothing was written");
      }
    }
    const std::string problem = copyToStream(s->stagingPath, fd);
    if (opened && ::close(fd) != 0 && problem.empty())
      throw OutputError(s->path, "cannot close " + s->destination.description + ": " + errnoText());
    if (!problem.empty())
      throw OutputError(s->path, "cannot write to " + s->destination.description + ": " + problem);
  }
  detail::ProcessRegistry& registry = detail::processRegistry();
  std::unique_lock<std::mutex> lock(registry.mutex);
  auto undo = [&] {
    std::error_code ec;
    for (auto m = done.rbegin(); m != done.rend(); ++m) {
      if (!m->previous.empty())
        fs::rename(m->previous, m->destination, ec);
      else
        fs::remove(m->destination, ec);
    }
  };
  // First every file an output replaces is kept (a hard link in the
  // staging folder's .previous), then the renames. Between the two, a
  // termination signal that has arrived ends the run as if the commit had
  // never begun: once a signal is sent, nothing more is committed.
  struct Planned {
    const std::string* output;  // the path the caller named
    fs::path file;
    Move move;
  };
  std::vector<Planned> plan;
  for (const auto& s : staged_) {
    if (s->destination.isStream()) continue;
    const fs::path previousFolder = fs::path(s->stagingFolder) / Staged::kPrevious;
    for (const fs::path& file : s->files()) {
      Move move{fs::path(s->folder) / file.filename(), {}};
      struct stat status {};
      if (::lstat(move.destination.c_str(), &status) == 0 && !S_ISDIR(status.st_mode)) {
        if (S_ISREG(status.st_mode)) keepModeAndOwnership(file, status);
        // A hard link keeps the replaced file until the commit is done. On a
        // file system without hard links the replaced file cannot be
        // restored after a later failed rename; renames within one folder
        // practically never fail once the staged files are complete.
        std::error_code ec;
        fs::create_directory(previousFolder, ec);
        const fs::path keep = previousFolder / file.filename();
        if (::link(move.destination.c_str(), keep.c_str()) == 0) move.previous = keep;
      }
      plan.push_back({&s->path, file, move});
    }
  }
  if (const int signal = detail::terminationSignalArrived()) detail::endBySignalWithRegistryLocked(signal);
  for (const Planned& step : plan) {
    std::error_code ec;
    fs::rename(step.file, step.move.destination, ec);
    if (ec) {
      undo();
      throw OutputError(*step.output, "cannot move " + step.file.filename().string() + " into place: " + ec.message());
    }
    done.push_back(step.move);
  }
  committed_ = true;
  lock.unlock();
  // The renames reach the disk with the folders' own entries.
  for (const auto& s : staged_)
    if (!s->destination.isStream()) (void)flushToDisk(s->folder, true);
  staged_.clear();  // removes the staging folders and the replaced files kept in them
}

void writeAtomically(const std::string& path, const OutputTransaction::Writer& writer) {
  OutputTransaction transaction;
  transaction.write(path, writer);
  transaction.commit();
}

std::size_t removeLeftoverStagingFolders(const std::string& folder) {
  detail::ProcessRegistry& registry = detail::processRegistry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  std::error_code ec;
  const std::vector<fs::path> leftovers = abandonedStagingFolders(folder, registry, ec);
  if (ec) throw OutputError(folder, "cannot list the folder to remove leftover staging folders: " + ec.message());
  for (const fs::path& leftover : leftovers) {
    fs::remove_all(leftover, ec);
    if (ec) throw OutputError(folder, "cannot remove the leftover staging folder " + leftover.filename().string() +
                                          ": " + ec.message());
  }
  return leftovers.size();
}

}  // namespace stvd::files

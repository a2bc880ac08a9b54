#include "stvd/system/files/output_transaction.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "process_registry.hpp"
#include "stvd/system/files/file_identity.hpp"

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

}  // namespace

detail::ProcessRegistry& detail::processRegistry() {
  static ProcessRegistry registry;
  return registry;
}

void checkOutputPath(const std::string& path) {
  if (path.empty()) throw OutputError("(output)", "the output path is empty");
  if (fs::path(path).filename().empty()) throw OutputError(path, "the output path names a folder, not a file");
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
  std::string stagingFolder;  // "<folder>/.stvd-staging-<pid>-<n>", registered
  std::string stagingPath;    // stagingFolder + the output's file name

  explicit Staged(std::string output) : path(std::move(output)), folder(folderOf(path)) {
    static std::atomic<unsigned> counter{0};
    detail::ProcessRegistry& registry = detail::processRegistry();
    const std::lock_guard<std::mutex> lock(registry.mutex);
    for (int attempt = 0; attempt < 100; ++attempt) {
      const fs::path candidate =
          fs::path(folder) / (kStagingFolderPrefix + std::to_string(::getpid()) + "-" + std::to_string(counter++));
      std::error_code ec;
      if (fs::create_directory(candidate, ec)) {
        stagingFolder = candidate.string();
        stagingPath = (candidate / fs::path(path).filename()).string();
        registry.stagingFolders.push_back(stagingFolder);
        return;
      }
      if (ec) throw OutputError(path, "cannot create a staging folder in '" + folder + "': " + ec.message());
    }
    throw OutputError(path, "cannot create a staging folder in '" + folder + "'");
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
    for (const auto& entry : fs::directory_iterator(stagingFolder, ec))
      if (entry.path() != fs::path(stagingPath) && entry.path().filename() != kPrevious) list.push_back(entry.path());
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
  for (const auto& s : staged_)
    if (sameFile(s->path, path)) throw OutputError(path, "the run writes this file twice (also as " + s->path + ")");
  staged_.push_back(std::make_unique<Staged>(path));
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
  for (const auto& s : staged_) {
    const fs::path previousFolder = fs::path(s->stagingFolder) / Staged::kPrevious;
    for (const fs::path& file : s->files()) {
      Move move{fs::path(s->folder) / file.filename(), {}};
      struct stat status {};
      if (::lstat(move.destination.c_str(), &status) == 0 && !S_ISDIR(status.st_mode)) {
        // A hard link keeps the replaced file until the commit is done. On a
        // file system without hard links the replaced file cannot be
        // restored after a later failed rename; renames within one folder
        // practically never fail once the staged files are complete.
        std::error_code ec;
        fs::create_directory(previousFolder, ec);
        const fs::path keep = previousFolder / file.filename();
        if (::link(move.destination.c_str(), keep.c_str()) == 0) move.previous = keep;
      }
      std::error_code ec;
      fs::rename(file, move.destination, ec);
      if (ec) {
        undo();
        throw OutputError(s->path, "cannot move " + file.filename().string() + " into place: " + ec.message());
      }
      done.push_back(move);
    }
  }
  committed_ = true;
  lock.unlock();
  // The renames reach the disk with the folders' own entries.
  for (const auto& s : staged_) (void)flushToDisk(s->folder, true);
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
  const std::string prefix = kStagingFolderPrefix;
  std::error_code ec;
  std::vector<fs::path> leftovers;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    std::error_code typeError;
    if (entry.path().filename().string().rfind(prefix, 0) != 0 || !entry.is_directory(typeError) ||
        entry.is_symlink(typeError))
      continue;
    // This process's names are unique (its id and a counter): compared by
    // name, however the folder was spelled.
    const auto& ours = registry.stagingFolders;
    if (std::none_of(ours.begin(), ours.end(),
                     [&](const std::string& f) { return fs::path(f).filename() == entry.path().filename(); }))
      leftovers.push_back(entry.path());
  }
  if (ec) throw OutputError(folder, "cannot list the folder to remove leftover staging folders: " + ec.message());
  for (const fs::path& leftover : leftovers) {
    fs::remove_all(leftover, ec);
    if (ec) throw OutputError(folder, "cannot remove the leftover staging folder " + leftover.filename().string() +
                                          ": " + ec.message());
  }
  return leftovers.size();
}

}  // namespace stvd::files

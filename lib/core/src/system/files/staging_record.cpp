#include "staging_record.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace stvd::files::detail {
namespace {

constexpr const char* kFirstLine = "stvd staging folder";
constexpr std::size_t kMaxRecordBytes = 4096;

std::string firstLineOf(const std::string& path) {
  try {
    const std::string text = readRegularFile(path, kMaxRecordBytes, /*truncate=*/true);
    return text.substr(0, text.find('\n'));
  } catch (const InputFileError&) {
    return {};
  }
}

std::string linkTarget(const char* path) {
  char target[PATH_MAX];
  const ssize_t n = ::readlink(path, target, sizeof target - 1);
  return n > 0 ? std::string(target, static_cast<std::size_t>(n)) : std::string();
}

std::string hostName() {
  char name[HOST_NAME_MAX + 1] = {};
  return ::gethostname(name, sizeof name - 1) == 0 ? std::string(name) : std::string();
}

/// The fields of /proc/<pid>/stat after the command name (which may hold
/// spaces and parentheses): [0] is the state, [19] the start time in clock
/// ticks after boot. Empty when there is no such process.
std::vector<std::string> processStatus(const std::string& pid, bool& exists) {
  exists = true;
  const int fd = ::open(("/proc/" + pid + "/stat").c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    exists = errno != ENOENT && errno != ESRCH;
    return {};
  }
  char buffer[2048];
  const ssize_t n = ::read(fd, buffer, sizeof buffer - 1);
  ::close(fd);
  if (n <= 0) {
    exists = !(n < 0 && errno == ESRCH);
    return {};
  }
  const std::string text(buffer, static_cast<std::size_t>(n));
  const std::size_t paren = text.rfind(')');
  if (paren == std::string::npos) return {};
  std::istringstream rest(text.substr(paren + 1));
  std::vector<std::string> fields;
  for (std::string f; rest >> f;) fields.push_back(f);
  return fields;
}

/// What identifies this process on this machine, as the record states it.
std::map<std::string, std::string> ownIdentity() {
  std::map<std::string, std::string> id;
  const std::string pid = std::to_string(::getpid());
  bool exists = false;
  const std::vector<std::string> status = processStatus(pid, exists);
  if (status.size() > 19) id["start"] = status[19];
  id["pid"] = pid;
  id["boot"] = firstLineOf("/proc/sys/kernel/random/boot_id");
  id["pidns"] = linkTarget("/proc/self/ns/pid");
  id["host"] = hostName();
  id["uid"] = std::to_string(::geteuid());
  return id;
}

const std::map<std::string, std::string>& identity() {
  static const std::map<std::string, std::string> id = ownIdentity();  // the pid never changes (no fork in use)
  return id;
}

bool parseRecord(const std::string& text, std::map<std::string, std::string>& fields) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kFirstLine) return false;
  while (std::getline(in, line)) {
    const std::size_t space = line.find(' ');
    if (space == std::string::npos || space == 0) return false;
    if (!fields.emplace(line.substr(0, space), line.substr(space + 1)).second) return false;
  }
  for (const char* key : {"pid", "start", "boot", "pidns", "host", "uid"})
    if (fields.count(key) == 0 || fields[key].empty()) return false;
  return true;
}

}  // namespace

std::string writeStagingRecord(const std::string& folder) {
  // The identity of a forked child is not its parent's: computed afresh
  // when the pid differs from the one cached.
  std::map<std::string, std::string> id = identity();
  if (id["pid"] != std::to_string(::getpid())) id = ownIdentity();
  for (const char* key : {"start", "boot", "pidns", "host"})
    if (id[key].empty()) return "this system does not tell the process's identity";  // no record: never removed
  std::ostringstream text;
  text << kFirstLine << "\n";
  for (const char* key : {"pid", "start", "boot", "pidns", "host", "uid"}) text << key << " " << id[key] << "\n";
  const std::string bytes = text.str();
  const std::string path = folder + "/" + kStagingRecordName;
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) return std::strerror(errno);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  const bool closed = ::close(fd) == 0;
  return done == bytes.size() && closed ? std::string() : std::string("cannot write the record");
}

bool isAbandonedStagingFolder(const std::string& folder, const std::string& name) {
  // The name: the prefix, the pid, '-', a counter.
  const std::string prefix = kStagingFolderPrefix;
  if (name.rfind(prefix, 0) != 0) return false;
  const std::string rest = name.substr(prefix.size());
  const std::size_t dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash + 1 >= rest.size()) return false;
  const std::string pid = rest.substr(0, dash);
  for (char c : rest)
    if ((c < '0' || c > '9') && c != '-') return false;
  if (rest.find('-', dash + 1) != std::string::npos) return false;

  struct stat status {};
  if (::lstat(folder.c_str(), &status) != 0 || !S_ISDIR(status.st_mode) || status.st_uid != ::geteuid())
    return false;
  // The record: a regular file of ours (no link followed), small, ours in
  // every field but the process.
  const std::string recordPath = folder + "/" + kStagingRecordName;
  const int fd = ::open(recordPath.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return false;
  struct stat recordStatus {};
  std::string text;
  if (::fstat(fd, &recordStatus) == 0 && S_ISREG(recordStatus.st_mode) && recordStatus.st_uid == ::geteuid() &&
      recordStatus.st_size > 0 && static_cast<std::size_t>(recordStatus.st_size) <= kMaxRecordBytes) {
    text.resize(static_cast<std::size_t>(recordStatus.st_size));
    const ssize_t n = ::read(fd, text.data(), text.size());
    text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  }
  ::close(fd);
  std::map<std::string, std::string> record;
  if (!parseRecord(text, record)) return false;
  const std::map<std::string, std::string>& own = identity();
  if (record["pid"] != pid || record["uid"] != std::to_string(::geteuid())) return false;
  // Only a process of this machine, as it runs now, can be looked up.
  for (const char* key : {"boot", "pidns", "host"}) {
    const auto mine = own.find(key);
    if (mine == own.end() || mine->second.empty() || record[key] != mine->second) return false;
  }
  if (pid == std::to_string(::getpid())) return false;  // this process's own folders are its business
  bool exists = false;
  const std::vector<std::string> process = processStatus(pid, exists);
  if (!exists) return true;
  if (process.size() <= 19) return false;  // it exists, and cannot be told apart: kept
  if (process[0] == "Z" || process[0] == "X") return true;  // ended, not yet reaped by its parent
  return process[19] != record["start"];  // the id now belongs to another process
}

}  // namespace stvd::files::detail

#include "stvd/system/files/file_identity.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <system_error>
#include <utility>

namespace fs = std::filesystem;

namespace stvd::files {
namespace {

struct Identity {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  std::string canonical;
};

Identity identify(const std::string& path) {
  Identity id;
  struct stat status {};
  if (::stat(path.c_str(), &status) == 0) {  // follows symbolic links
    id.exists = true;
    id.device = status.st_dev;
    id.inode = status.st_ino;
  }
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) canonical = fs::absolute(path, ec).lexically_normal();
  id.canonical = canonical.string();
  return id;
}

bool same(const Identity& a, const Identity& b) {
  if (a.exists && b.exists) return a.device == b.device && a.inode == b.inode;
  return a.canonical == b.canonical;
}

/// The first (lowest) index of the files added that are the same file as a
/// given one, by the rule of same(): device and inode when both exist, the
/// canonical path otherwise.
class IdentityIndex {
 public:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  void add(const Identity& id, std::size_t index) {
    if (id.exists) byInode_.emplace(std::make_pair(id.device, id.inode), index);  // keeps the first
    (id.exists ? existingByPath_ : missingByPath_).emplace(id.canonical, index);
  }

  std::size_t first(const Identity& id) const {
    std::size_t found = kNone;
    auto take = [&found](const auto& map, const auto& key) {
      if (const auto at = map.find(key); at != map.end()) found = std::min(found, at->second);
    };
    if (id.exists) {
      take(byInode_, std::make_pair(id.device, id.inode));
    } else {
      take(existingByPath_, id.canonical);
    }
    take(missingByPath_, id.canonical);
    return found;
  }

 private:
  std::map<std::pair<dev_t, ino_t>, std::size_t> byInode_;
  std::map<std::string, std::size_t> existingByPath_, missingByPath_;
};

std::string conflictMessage(const RunFile& output, const RunFile& other, bool otherIsOutput) {
  std::string line = output.path + ": the " + output.role + " is the " + other.role;
  if (other.path != output.path) line += " (" + other.path + ", the same file)";
  line += otherIsOutput ? "; give each output a file of its own"
                        : "; stvd never writes over an input, choose another output file";
  return line;
}

}  // namespace

bool sameFile(const std::string& a, const std::string& b) { return same(identify(a), identify(b)); }

void checkOutputsAreNotInputs(const std::vector<RunFile>& inputs, const std::vector<RunFile>& outputs) {
  // Files indexed by identity, so that a cohort of many thousand subjects is
  // checked in n log n, not n^2; the first conflict found (and named) is the
  // one the pairwise comparison in order would find.
  IdentityIndex inputIndex, outputIndex;
  for (std::size_t i = 0; i < inputs.size(); ++i) inputIndex.add(identify(inputs[i].path), i);
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const Identity id = identify(outputs[o].path);
    if (const std::size_t i = inputIndex.first(id); i != IdentityIndex::kNone)
      throw FileConflict(conflictMessage(outputs[o], inputs[i], false));
    if (const std::size_t e = outputIndex.first(id); e != IdentityIndex::kNone)
      throw FileConflict(conflictMessage(outputs[o], outputs[e], true));
    outputIndex.add(id, o);
  }
}

}  // namespace stvd::files

#include "stvd/files/file_identity.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <system_error>

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
  std::vector<Identity> inputIds, outputIds;
  inputIds.reserve(inputs.size());
  for (const RunFile& f : inputs) inputIds.push_back(identify(f.path));
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const Identity id = identify(outputs[o].path);
    for (std::size_t i = 0; i < inputs.size(); ++i)
      if (same(id, inputIds[i])) throw FileConflict(conflictMessage(outputs[o], inputs[i], false));
    for (std::size_t e = 0; e < o; ++e)
      if (same(id, outputIds[e])) throw FileConflict(conflictMessage(outputs[o], outputs[e], true));
    outputIds.push_back(id);
  }
}

}  // namespace stvd::files

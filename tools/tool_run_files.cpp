#include "tool_run_files.hpp"

#include <stdexcept>

#include "command_line.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tool {

void RunFiles::inputTetMesh(const std::string& role, const std::string& path) {
  const std::string base = tetmesh::tetGenBaseName(path);
  for (const char* suffix : {".node", ".ele", ".face"}) inputFile(std::string(suffix) + " file of the " + role, base + suffix);
}

void RunFiles::check() const {
  try {
    imaging::RunFiles::check();
  } catch (const files::FileConflict& e) {
    throw ToolError(kExitUsage, e.what());
  } catch (const std::runtime_error& e) {  // files::OutputError, imaging::ImageIoError
    throw ToolError(kExitOutput, e.what());
  }
}

}  // namespace stvd::tool

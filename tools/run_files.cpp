#include "run_files.hpp"

#include "command_line.hpp"
#include "stvd/files/output_transaction.hpp"
#include "stvd/itk/image_files.hpp"
#include "stvd/itk/image_io_error.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tool {
namespace {

/// "data file of the tensor input" for the companions after the first file.
void addWithCompanions(std::vector<files::RunFile>& list, const std::string& role,
                       const std::vector<std::string>& paths) {
  for (std::size_t i = 0; i < paths.size(); ++i)
    list.push_back({i == 0 ? role : "data file of the " + role, paths[i]});
}

}  // namespace

void RunFiles::inputImage(const std::string& role, const std::string& path) {
  if (!path.empty()) addWithCompanions(inputs_, role, imaging::imageFilesRead(path));
}

void RunFiles::inputTetMesh(const std::string& role, const std::string& path) {
  const std::string base = tetmesh::tetGenBaseName(path);
  for (const char* suffix : {".node", ".ele", ".face"})
    inputs_.push_back({std::string(suffix) + " file of the " + role, base + suffix});
}

void RunFiles::inputFile(const std::string& role, const std::string& path) {
  if (!path.empty()) inputs_.push_back({role, path});
}

void RunFiles::outputImage(const std::string& role, const std::string& path) {
  if (path.empty()) return;
  addWithCompanions(outputs_, role, imaging::imageFilesWritten(path));
  imageOutputs_.push_back(path);
}

void RunFiles::outputFile(const std::string& role, const std::string& path) {
  if (!path.empty()) outputs_.push_back({role, path});
}

void RunFiles::check() const {
  try {
    files::checkOutputsAreNotInputs(inputs_, outputs_);
  } catch (const files::FileConflict& e) {
    throw ToolError(kExitUsage, e.what());
  }
  try {
    for (const files::RunFile& output : outputs_) files::checkOutputPath(output.path);
    for (const std::string& image : imageOutputs_) imaging::checkImageOutputCompanions(image);
  } catch (const std::runtime_error& e) {  // files::OutputError, imaging::ImageIoError
    throw ToolError(kExitOutput, e.what());
  }
}

}  // namespace stvd::tool

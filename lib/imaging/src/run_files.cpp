#include "stvd/imaging/run_files.hpp"

#include "stvd/imaging/image_files.hpp"
#include "stvd/system/files/output_transaction.hpp"

namespace stvd::imaging {
namespace {

/// "data file of the tensor input" for the companions after the first file.
void addWithCompanions(std::vector<files::RunFile>& list, const std::string& role,
                       const std::vector<std::string>& paths) {
  for (std::size_t i = 0; i < paths.size(); ++i)
    list.push_back({i == 0 ? role : "data file of the " + role, paths[i]});
}

}  // namespace

void RunFiles::inputImage(const std::string& role, const std::string& path) {
  if (!path.empty()) addWithCompanions(inputs_, role, imageFilesRead(path));
}

void RunFiles::inputFile(const std::string& role, const std::string& path) {
  if (!path.empty()) inputs_.push_back({role, path});
}

void RunFiles::outputImage(const std::string& role, const std::string& path) {
  if (path.empty()) return;
  addWithCompanions(outputs_, role, imageFilesWritten(path));
  imageOutputs_.push_back(path);
}

void RunFiles::outputFile(const std::string& role, const std::string& path) {
  if (!path.empty()) outputs_.push_back({role, path});
}

void RunFiles::check() const {
  files::checkOutputsAreNotInputs(inputs_, outputs_);
  for (const files::RunFile& output : outputs_) files::checkOutputPath(output.path);
  for (const std::string& image : imageOutputs_) checkImageOutputCompanions(image);
}

}  // namespace stvd::imaging

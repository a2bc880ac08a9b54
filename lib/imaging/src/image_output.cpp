#include "stvd/imaging/detail/image_output.hpp"

#include "stvd/errors.hpp"
#include "stvd/system/files/output_transaction.hpp"

namespace stvd::imaging::detail {

void writeAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  try {
    files::writeAtomically(path, write);
  } catch (const files::OutputError& e) {
    std::string problem = e.what();
    problem.erase(0, e.path().size() + 2);
    throw ImageIoError(path, problem);
  }
}

}  // namespace stvd::imaging::detail

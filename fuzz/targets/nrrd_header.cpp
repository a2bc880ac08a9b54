// Our handling of NRRD headers: the list of data files a header names (read
// for every image input before anything else, to compare inputs with
// outputs), the screening that runs before NrrdIO, and, for headers it lets
// through, the fields we read through NrrdIO ourselves (space, measurement
// frame, kind of a masked tensor file).
#include "stvd/imaging/detail/image_header_screening.hpp"
#include "nrrd_header.hpp"
#include "fuzz_input_file.hpp"
#include "stvd/imaging/image_files.hpp"
#include "stvd/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const stvd::fuzz::FuzzInputFile input("header.nrrd", data, size);
  stvd::imaging::imageFilesRead(input.path());
  try {
    stvd::imaging::detail::screenImageFile(input.path());
    stvd::imaging::detail::readNrrdTensorHeader(input.path());
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}

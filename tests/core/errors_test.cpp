// The errors stvd reports form one hierarchy (stvd/errors.hpp): every one is
// a stvd::Error that says its kind, and keeps the standard base that C++
// callers catch and that pybind11 turns into ValueError or RuntimeError.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <type_traits>

#include "stvd/errors.hpp"

namespace {

using namespace stvd;

template <class E, class Standard>
void expectErrorOf(const E& error, ErrorKind kind, const std::string& message) {
  static_assert(std::is_base_of_v<Error, E>, "every error derives from stvd::Error");
  static_assert(std::is_base_of_v<Standard, E>, "and keeps its standard base");
  try {
    throw error;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind);
    EXPECT_EQ(std::string(e.what()), message);
  }
  try {
    throw error;
  } catch (const Standard& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(Errors, EveryErrorIsAStvdErrorOfItsKindWithItsStandardBaseAndOneMessage) {
  expectErrorOf<OptionError, std::invalid_argument>(OptionError("--k: 0"), ErrorKind::Option, "--k: 0");
  expectErrorOf<InputError, std::invalid_argument>(InputError("bad mesh"), ErrorKind::Input, "bad mesh");
  expectErrorOf<NothingToCompute, std::invalid_argument>(NothingToCompute("empty domain"),
                                                         ErrorKind::NothingToCompute, "empty domain");
  expectErrorOf<SurfaceError, InputError>(SurfaceError("edge (1, 2) has 3 faces"), ErrorKind::Input,
                                          "edge (1, 2) has 3 faces");
  expectErrorOf<files::OutputError, std::runtime_error>(files::OutputError("d.nii", "No space left on device"),
                                                        ErrorKind::Output, "d.nii: No space left on device");
  expectErrorOf<files::FileConflict, std::runtime_error>(files::FileConflict("d.nii: the map is the input"),
                                                         ErrorKind::Option, "d.nii: the map is the input");
  expectErrorOf<files::InputFileError, std::runtime_error>(files::InputFileError("t.nii", "is a FIFO, not a regular file"),
                                                           ErrorKind::Input, "t.nii: is a FIFO, not a regular file");
  expectErrorOf<imaging::ImageIoError, std::runtime_error>(imaging::ImageIoError("t.nii", "truncated"),
                                                           ErrorKind::Input, "t.nii: truncated");
  expectErrorOf<surface_io::MeshFileError, std::runtime_error>(surface_io::MeshFileError("m.off: line 3"),
                                                               ErrorKind::Input, "m.off: line 3");
  expectErrorOf<tetmesh::TetMeshError, std::runtime_error>(tetmesh::TetMeshError("m.ele: inverted"),
                                                           ErrorKind::Input, "m.ele: inverted");
}

TEST(Errors, FileErrorsNameTheirFile) {
  EXPECT_EQ(files::OutputError("out/d.nii", "x").path(), "out/d.nii");
  EXPECT_EQ(imaging::ImageIoError("in/t.nrrd", "x").path(), "in/t.nrrd");
  EXPECT_EQ(files::InputFileError("in/t.nii", "no such file").problem(), "no such file");
}

}  // namespace

// The files a Python call writes, as the tool writes its own: the inputs and
// outputs of the call declared and compared by identity before anything is
// written (imaging::RunFiles), and the outputs written all or nothing
// through the library's output transaction (files::OutputTransaction).
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "stvd/system/files/file_identity.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/imaging/run_files.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/itk/image_grid.hpp"

namespace py = pybind11;

namespace stvd::python {

void bindFiles(py::module_& m) {
  // An output that is an input or another output is bad input to the call;
  // an output that cannot be written is an operating-system error.
  py::register_exception<files::FileConflict>(m, "FileConflictError", PyExc_ValueError);
  py::register_exception<files::OutputError>(m, "OutputError", PyExc_OSError);

  m.def("is_image_path", &imaging::hasImageExtension, py::arg("path"),
        "Whether stvd writes `path` as an image (.nii, .nii.gz, .nrrd, .nhdr, .mif, .mif.gz).");
  m.def(
      "require_image_on_grid",
      [](const std::string& path, const std::string& reference, const std::string& subject) {
        imaging::requireImageOnGrid(path, imaging::readImageGrid(reference), subject, reference);
      },
      py::arg("path"), py::arg("reference"), py::arg("subject"), py::call_guard<py::gil_scoped_release>(),
      "ValueError '<path>: <subject> on another grid than <reference> (...)' unless the two image files' headers "
      "declare the same grid; no data are read (stvd/itk/image_grid.hpp).");

  m.def(
      "read_label_image",
      [](const std::string& path, const std::string& reference, const std::string& subject) {
        imaging::readLabelImageOnGrid(path, imaging::readImageGrid(reference), subject, reference);
      },
      py::arg("path"), py::arg("reference"), py::arg("subject"), py::call_guard<py::gil_scoped_release>(),
      "Reads the label image `path` as the tool reads one on the grid of the image file `reference`, and drops "
      "it: the library's ValueError for a file it cannot read (the message the tool and every call give).");

  py::class_<imaging::RunFiles>(m, "RunFiles", "The files one call reads and writes (stvd/imaging/run_files.hpp).")
      .def(py::init<>())
      .def("input_image", &imaging::RunFiles::inputImage, py::arg("role"), py::arg("path"))
      .def("input_file", &imaging::RunFiles::inputFile, py::arg("role"), py::arg("path"))
      .def("output_image", &imaging::RunFiles::outputImage, py::arg("role"), py::arg("path"))
      .def("output_file", &imaging::RunFiles::outputFile, py::arg("role"), py::arg("path"))
      .def("check", &imaging::RunFiles::check)
      .def(
          "check_identities",
          [](const imaging::RunFiles& f) { files::checkOutputsAreNotInputs(f.inputs(), f.outputs()); },
          "check() without the outputs' folders: for outputs whose folders are made later.")
      .def_property_readonly("inputs",
                             [](const imaging::RunFiles& f) {
                               py::list l;
                               for (const files::RunFile& r : f.inputs()) l.append(py::make_tuple(r.role, r.path));
                               return l;
                             })
      .def_property_readonly("outputs", [](const imaging::RunFiles& f) {
        py::list l;
        for (const files::RunFile& r : f.outputs()) l.append(py::make_tuple(r.role, r.path));
        return l;
      });

  m.attr("STAGING_FOLDER_PREFIX") = files::kStagingFolderPrefix;
  m.def("remove_leftover_staging_folders", &files::removeLeftoverStagingFolders, py::arg("folder"),
        "Removes the staging folders that killed runs left in `folder`; returns how many.");

  py::class_<files::OutputTransaction>(m, "OutputTransaction",
                                       "Outputs staged next to their final paths and moved into place together.")
      .def(py::init<>())
      .def(
          "write",
          [](files::OutputTransaction& t, const std::string& path, const py::function& writer) {
            // The writer is Python: the GIL stays held while it runs.
            t.write(path, [&writer](const std::string& staging) { writer(staging); });
          },
          py::arg("path"), py::arg("writer"),
          "Calls writer(staging_path), which must write the file there, and flushes it to disk.")
      // A FIFO output may wait for its reader: other threads run meanwhile.
      .def("commit", &files::OutputTransaction::commit, py::call_guard<py::gil_scoped_release>());
}

}  // namespace stvd::python

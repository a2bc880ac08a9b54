// The extension module stvd._core: the library's defaults, its errors as
// Python exceptions, and the bindings of volumes and meshes. The public API
// is the pure-Python package around it (python/stvd/).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <variant>

#include "bindings.hpp"
#include "propagation_keywords.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/itk_messages.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"

namespace py = pybind11;

namespace {

py::object pythonValue(const stvd::OptionValue& value) {
  if (const auto* b = std::get_if<bool>(&value)) return py::bool_(*b);
  if (const auto* i = std::get_if<long long>(&value)) return py::int_(*i);
  if (const auto* x = std::get_if<double>(&value)) return py::float_(*x);
  if (const auto* t = std::get_if<std::string>(&value)) return py::str(*t);
  if (const auto* p = std::get_if<std::array<double, 3>>(&value)) return py::make_tuple((*p)[0], (*p)[1], (*p)[2]);
  return py::none();
}

/// The commands by the names `stvd help --markdown` and the package use.
const std::pair<stvd::OptionCommand, const char*> kCommandNames[] = {
    {stvd::kDistanceCommand, "distance"},       {stvd::kPathCommand, "path"},
    {stvd::kConnectivityCommand, "connectivity"}, {stvd::kSurfaceDistanceCommand, "surface"},
    {stvd::kTetMeshDistanceCommand, "tet-mesh"},  {stvd::kInfoCommand, "info"},
    {stvd::kCohortCommand, "cohort"},
    {stvd::kFodDistanceCommand, "fod-distance"}};

py::list commandNames(stvd::OptionCommands commands) {
  py::list names;
  for (const auto& [command, name] : kCommandNames)
    if (commands & command) names.append(name);
  return names;
}

/// The library's option declarations (stvd/front_end/option_declarations.hpp) as
/// dicts: what the package's keywords and the cohort command line are
/// checked and documented with.
py::list optionDeclarations() {
  using namespace stvd;
  static const char* const kTypes[] = {"switch", "integer", "index", "number", "choice", "text", "point", "voxel"};
  py::list list;
  for (const OptionDeclaration& o : python::optionDeclarations()) {
    py::dict d;
    d["flag"] = o.flag;
    d["value_name"] = o.valueName;
    d["keyword"] = o.keyword.empty() ? py::object(py::none()) : py::object(py::str(o.keyword));
    d["commands"] = commandNames(o.commands);
    d["keyword_commands"] = commandNames(o.keyword.empty() ? 0 : o.keywordCommands.value_or(o.commands));
    d["keyword_is_negation"] = o.keywordIsNegation;
    d["keyword_takes_number"] = o.keywordTakesNumber;
    d["type"] = kTypes[static_cast<int>(o.type)];
    py::list choices, keywordChoices;
    for (const OptionChoice& c : o.choices) {
      choices.append(c.name);
      keywordChoices.append(c.name.substr(0, c.name.find(':')));
    }
    d["choices"] = choices;
    d["keyword_choices"] = keywordChoices;
    d["minimum"] = o.range.min ? py::object(py::float_(*o.range.min)) : py::object(py::none());
    d["maximum"] = o.range.max ? py::object(py::float_(*o.range.max)) : py::object(py::none());
    py::dict defaults, help;
    for (const auto& [command, name] : kCommandNames) {
      if (!(o.commands & command) && !(o.keywordCommands.value_or(o.commands) & command)) continue;
      defaults[name] = pythonValue(o.defaultFor(command));
      if (o.takes(command)) help[name] = optionHelpText(o, command);
    }
    d["defaults"] = defaults;
    d["help"] = help;
    list.append(d);
  }
  return list;
}

/// Every default the Python API has, from the options' declarations (so
/// from the library's constants, as the tool's help prints them): the k a
/// propagation runs with when none is given is its kind of domain's
/// (defaultMemoryDepth), as in the tool.
py::dict defaults() {
  using namespace stvd;
  py::dict d;
  for (const OptionDeclaration& o : python::optionDeclarations()) {
    if (o.keyword.empty() || d.contains(o.keyword)) continue;
    if (o.type == OptionType::Switch) {
      d[o.keyword.c_str()] = o.keywordIsNegation;  // a switch is off unless given
      continue;
    }
    const OptionValue& value = o.defaults[static_cast<int>(OptionDomain::VoxelGrid)];
    const OptionValue& surface = o.defaults[static_cast<int>(OptionDomain::Surface)];
    if (!std::holds_alternative<std::monostate>(value)) d[o.keyword.c_str()] = pythonValue(value);
    else if (!std::holds_alternative<std::monostate>(surface)) d[o.keyword.c_str()] = pythonValue(surface);
  }
  const OptionDeclaration& k = propagationOption("--k");
  d["surface_k"] = pythonValue(k.defaults[static_cast<int>(OptionDomain::Surface)]);
  d["tet_mesh_k"] = pythonValue(k.defaults[static_cast<int>(OptionDomain::TetMesh)]);
  // One chain measure for every kind of domain; the key stays for scripts
  // written when surfaces had their own.
  d["surface_chain_measure"] =
      pythonValue(propagationOption("--chain-measure").defaults[static_cast<int>(OptionDomain::Surface)]);
  // Unset: the cap depends on the tensor kind (diffusion tensors: the
  // declared default, kDefaultMaxAnisotropy; a metric as given).
  d["diffusion_max_anisotropy"] = d["max_anisotropy"];
  d["max_anisotropy"] = py::none();
  d["max_k"] = static_cast<int>(*k.range.max);
  d["max_steiner"] = static_cast<int>(*propagationOption("--steiner").range.max);
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "stvd's C++ library: the extension module under the stvd package.";
  m.attr("__version__") = STVD_VERSION_TEXT;
  m.attr("NO_VERTEX") = stvd::kNoVertex;
  // The ITK inside this module is ours alone (Python's own ITK, if any, is
  // another copy): its messages during our reads stay off the terminal.
  stvd::imaging::installItkMessageFilter();
  m.def("defaults", &defaults, "The library's defaults for every option of the Python API.");
  m.def("option_declarations", &optionDeclarations,
        "The library's option declarations: flags, keywords, commands, choices, ranges, defaults and help.");

  // The library's one-line messages become ValueError (its option, input and
  // domain errors derive from std::invalid_argument, which pybind11 already
  // turns into ValueError); file errors, which are runtime errors in C++,
  // are bad input here too. A run refused for lack of memory is MemoryError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const stvd::imaging::ImageIoError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const stvd::surface_io::MeshFileError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const stvd::python::MemoryShortfallError& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    }
  });

  stvd::python::bindFiles(m);
  stvd::python::bindVolumes(m);
  stvd::python::bindMeshes(m);
  stvd::python::bindSurfaceFiles(m);
  stvd::python::bindFod(m);
}

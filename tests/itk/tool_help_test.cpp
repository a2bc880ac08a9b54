// The help cannot drift from the library: every default that a command's
// --help prints is the library's constant, every declared option is taken
// by the commands that list it and refused with the standard message by the
// others, and docs/cli.md's option tables are the declarations'.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "command_options.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/tetmesh/tet_mesh_options.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

/// A command as its help is asked for, and the part of the help that is its own.
struct HelpCall {
  std::string name;
  std::vector<std::string> arguments;
  std::string from, to;  // the section between these lines (empty: the whole text)
};

const std::vector<HelpCall>& helpCalls() {
  static const std::vector<HelpCall> calls{
      {"distance", {"distance", "--help"}, "", "=== Polygon surfaces"},
      {"surface", {"distance", "--help"}, "=== Polygon surfaces", "=== Tetrahedral meshes"},
      {"tet-mesh", {"distance", "--help"}, "=== Tetrahedral meshes", ""},
      {"surface", {"distance", "mesh.obj", "--help"}, "", ""},
      {"tet-mesh", {"distance", "mesh.node", "--help"}, "", ""},
      {"path", {"path", "--help"}, "", ""},
      {"connectivity", {"connectivity", "--help"}, "", ""},
      {"info", {"info", "--help"}, "", ""},
  };
  return calls;
}

/// The defaults as the library holds them, per command: its constants and
/// the defaults of its option structs, never the declarations'.
std::map<std::string, std::string> libraryDefaults(const std::string& command) {
  const PropagationChoice choice;
  const imaging::TensorInputOptions tensor;
  const PathTracingOptions tracing;
  const auto number = [](double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  };
  const std::map<std::string, std::string> propagation{
      {"--method", methodName(choice)},
      {"--chain-measure", chainMeasureName(kDefaultChainMeasure)},
  };
  const std::map<std::string, std::string> metric{
      {"--tensor-kind", imaging::tensorKindName(tensor.metric.kind)},
      {"--diffusion-metric", imaging::diffusionMetricName(tensor.metric.diffusionMetric)},
      {"--max-anisotropy", number(imaging::kDefaultMaxAnisotropy)},
  };
  std::map<std::string, std::string> d;
  if (command == "distance" || command == "path" || command == "connectivity") {
    d = propagation;
    d.insert(metric.begin(), metric.end());
    d["--k"] = std::to_string(defaultMemoryDepth<VoxelGridDomain>());
    d["--stencil"] = choice.stencil;
    d["--domain-connectivity"] = std::to_string(static_cast<int>(choice.connectivity));
    const imaging::FodCostOptions fod;
    d["--fod-floor"] = number(fod.floor);
    d["--fod-power"] = number(fod.power);
  }
  if (command == "distance") d["--unreachable-value"] = number(kDefaultUnreachableValue);
  if (command == "path") {
    d["--step"] = number(tracing.stepFraction);
    d["--smooth"] = std::to_string(tracing.smoothingPasses);
  }
  if (command == "surface") {
    d = propagation;
    d["--k"] = std::to_string(defaultMemoryDepth<SurfaceDomain>());
    d["--metric"] = "isotropic";
    d["--seed-at"] = "vertex";
  }
  if (command == "tet-mesh") {
    d = propagation;
    d.insert(metric.begin(), metric.end());
    d["--k"] = std::to_string(defaultMemoryDepth<CellMeshDomain>());
    d["--unreachable-value"] = number(kDefaultUnreachableValue);
    d["--tensor-order"] = imaging::tensorOrderName(imaging::kDefaultAttributeTensorOrder);
    d["--tensor-attribute"] = std::to_string(tetmesh::kDefaultFirstTensorAttribute);
    d["--outside-image"] = "error";
    d["--seed-at"] = "vertex";
  }
  if (command == "info") d["--max-anisotropy"] = number(imaging::kDefaultMaxAnisotropy);
  return d;
}

/// The option entries of a help text: each "  --flag ..." line with the
/// lines indented under it, as one line of text, by the entry's long flag.
std::map<std::string, std::string> optionEntries(const std::string& help) {
  std::map<std::string, std::string> entries;
  std::istringstream lines(help);
  std::string line, flag;
  const std::regex entry(R"(^  (?:-\w, )?(--[\w-]+))");
  for (std::smatch m; std::getline(lines, line);) {
    if (std::regex_search(line, m, entry)) {
      flag = m[1];
      entries[flag] = line;
    } else if (!flag.empty() && line.rfind("                          ", 0) == 0) {
      entries[flag] += " " + line.substr(line.find_first_not_of(' '));
    } else {
      flag.clear();
    }
  }
  return entries;
}

/// The defaults an entry states: "6 (default ..." after a list separator
/// for a choice, "(default 6" for a number. Empty when it states none.
std::vector<std::string> statedDefaults(const std::string& entry) {
  std::vector<std::string> found;
  const std::regex choice(R"((?:^ *--\S+(?: \S+)? +|[:,;] | or )([\w.:-]+) \(default[):;])");
  const std::regex number(R"(\(default (-?[0-9][\w.]*))");
  for (const std::regex* pattern : {&choice, &number})
    for (auto m = std::sregex_iterator(entry.begin(), entry.end(), *pattern); m != std::sregex_iterator(); ++m)
      found.push_back((*m)[1]);
  return found;
}

bool sameValue(const std::string& printed, const std::string& library) {
  if (printed == library) return true;
  char* end = nullptr;
  const double a = std::strtod(printed.c_str(), &end);
  if (end == printed.c_str() || *end) return false;
  return a == std::strtod(library.c_str(), nullptr);
}

TEST(ToolHelp, EveryDefaultItPrintsIsTheLibrarysConstant) {
  for (const HelpCall& call : helpCalls()) {
    const ToolRun run = runTool(call.arguments);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    std::string help = run.out;
    if (!call.from.empty()) help = help.substr(help.find(call.from));
    if (!call.to.empty()) help = help.substr(0, help.find(call.to));
    const std::map<std::string, std::string> library = libraryDefaults(call.name);
    const std::map<std::string, std::string> entries = optionEntries(help);
    std::map<std::string, std::string> printed;
    for (const auto& [flag, entry] : entries) {
      const std::vector<std::string> stated = statedDefaults(entry);
      ASSERT_LE(stated.size(), 1u) << call.name << " " << flag << " states several defaults: " << entry;
      if (stated.empty()) continue;
      printed[flag] = stated[0];
      const auto expected = library.find(flag);
      ASSERT_NE(expected, library.end()) << call.name << " " << flag << " prints a default (" << stated[0]
                                         << ") the test does not know the library's constant of";
      EXPECT_TRUE(sameValue(stated[0], expected->second))
          << call.name << " --help: " << flag << " (default " << stated[0] << "), but the library's is "
          << expected->second << ": " << entry;
    }
    for (const auto& [flag, value] : library)
      EXPECT_TRUE(printed.count(flag)) << call.name << " --help does not state the default of " << flag << " ("
                                       << value << ")";
  }
}

/// A value `option` accepts.
std::string validValue(const OptionDeclaration& o) {
  switch (o.type) {
    case OptionType::Integer:
    case OptionType::Index:
      return std::to_string(static_cast<long long>(o.range.min.value_or(1.0)));
    case OptionType::Number:
      return std::to_string(o.range.min ? *o.range.min + (o.range.minExcluded ? 0.5 : 0.0) : 1.0);
    case OptionType::Choice:
      return o.choices.front().name.substr(0, o.choices.front().name.find(':'));
    case OptionType::Point:
    case OptionType::Voxel:
      return "1,2,3";
    default:
      return "x";
  }
}

/// How readCommandLine answers `arguments` for `command`: "" when it takes
/// them all (up to --help), otherwise its usage error.
std::string readingError(OptionCommand command, std::vector<std::string> arguments) {
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  try {
    stvd::tool::readCommandLine(command, static_cast<int>(argv.size()), argv.data(), 0, [] { return std::string(); });
  } catch (const stvd::tool::ToolError& e) {
    if (e.exitCode() == stvd::tool::kExitOk) return "";
    return std::to_string(e.exitCode()) + ": " + e.what();
  }
  return "";
}

TEST(ToolHelp, EveryOptionIsTakenByTheCommandsThatListItAndRefusedByTheOthers) {
  using stvd::tool::CommandForm;
  const std::map<OptionCommand, std::vector<std::string>> prefixes{
      {kDistanceCommand, {"distance"}},          {kPathCommand, {"path"}},
      {kConnectivityCommand, {"connectivity"}},  {kSurfaceDistanceCommand, {"distance", "mesh.obj"}},
      {kTetMeshDistanceCommand, {"distance", "mesh.node"}}, {kInfoCommand, {"info"}}};
  int refusals = 0;
  for (const CommandForm& form : stvd::tool::commandForms()) {
    // The real tool takes every option the command lists, all on one line
    // (--help ends the run once they are read) and its help lists each.
    std::vector<std::string> all = prefixes.at(form.command);
    std::vector<std::string> refused;
    for (const OptionDeclaration& o : stvd::tool::allOptionDeclarations()) {
      if (o.flag == "--help") continue;
      std::vector<std::string> given{o.flag};
      if (o.type != OptionType::Switch) given.push_back(validValue(o));
      if (o.takes(form.command)) {
        all.insert(all.end(), given.begin(), given.end());
        continue;
      }
      // Every other one is refused with the standard message, or the
      // command's reason for it. (--seed-vertex makes `stvd distance` a
      // surface call, by design.)
      if (o.flag == "--seed-vertex" && form.command == kDistanceCommand) continue;
      const std::string expected = (o.refusedBy & form.command)
                                       ? o.flag + " " + o.refusal
                                       : "unknown option '" + o.flag + "'" + form.kind + " (see " + form.helpCall +
                                             ")";
      EXPECT_EQ(readingError(form.command, given), "2: " + expected) << form.name;
      if (refused.empty()) refused = given;
      ++refusals;
    }
    all.push_back("--help");
    const ToolRun run = runTool(all);
    ASSERT_EQ(run.exitCode, 0) << form.name << ": " << run.err;
    for (const OptionDeclaration& o : stvd::tool::allOptionDeclarations()) {
      if (o.takes(form.command)) {
        EXPECT_NE(run.out.find(o.flag), std::string::npos) << form.name << ": " << o.flag;
      }
    }
    // And the real tool refuses them with that message.
    std::vector<std::string> arguments = prefixes.at(form.command);
    arguments.insert(arguments.end(), refused.begin(), refused.end());
    const ToolRun refusal = runTool(arguments);
    EXPECT_EQ(refusal.exitCode, 2) << form.name;
    EXPECT_EQ(refusal.err, "stvd: " + readingError(form.command, refused).substr(3) + "\n") << form.name;
  }
  EXPECT_GT(refusals, 100);
}

TEST(ToolHelp, DocsOptionTablesAreTheDeclarations) {
  std::ifstream in(std::string(STVD_DOCS_DIR) + "/cli.md");
  std::stringstream page;
  page << in.rdbuf();
  const std::string text = page.str();
  // Plain searches, not std::regex: libstdc++'s regex recurses once per
  // character of a lazy [\s\S]*? match, which overflows the stack on a
  // table this long under AddressSanitizer (the sanitizer pass runs this).
  const std::string open = "<!-- generated by `stvd help --markdown ";
  const std::string close = "<!-- end of generated options -->";
  int blocks = 0;
  for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at), ++blocks) {
    const std::size_t wordsEnd = text.find('`', at + open.size());
    const std::size_t lineEnd = text.find('\n', at);
    const std::size_t end = text.find(close, lineEnd);
    ASSERT_TRUE(wordsEnd != std::string::npos && lineEnd != std::string::npos && end != std::string::npos &&
                wordsEnd < lineEnd && text.compare(lineEnd - 3, 3, "-->") == 0)
        << "docs/cli.md: a generated block at byte " << at << " is not closed";
    const std::string call = text.substr(at + open.size(), wordsEnd - at - open.size());
    const std::string table = text.substr(lineEnd + 1, end - lineEnd - 1);
    std::vector<std::string> arguments{"help", "--markdown"};
    std::istringstream words(call);
    for (std::string word; words >> word;) arguments.push_back(word);
    const ToolRun run = runTool(arguments);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(table, run.out) << "docs/cli.md: the tables of `stvd help --markdown " << call
                              << "` are not the declarations'; run scripts/update_cli_docs.py";
    at = end + close.size();
  }
  // distance; path and connectivity; surfaces and tetrahedral meshes; info.
  EXPECT_EQ(blocks, 6);
}

}  // namespace
}  // namespace stvd::testing

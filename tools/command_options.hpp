// The options of every subcommand, from their declarations: the library's
// (propagation, paths, regions, meshes, tensor files, seeds: see
// stvd/front_end/option_declarations.hpp) and the tool's own (outputs, --help). One
// reader parses every command line with them, and the help and
// docs/cli.md's option tables are printed from them (option_help.hpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stvd/front_end/option_declarations.hpp"

namespace stvd::tool {

/// Every option the tool knows, grouped (OptionGroup) and in the order the
/// help lists them.
const std::vector<OptionDeclaration>& allOptionDeclarations();
/// The declaration with this flag, short flag or keyword (std::logic_error
/// when there is none).
const OptionDeclaration& toolOption(const std::string& name);

/// A command as its messages name it.
struct CommandForm {
  OptionCommand command;
  std::string name;      ///< for `stvd help --markdown NAME`: distance, path, surface, tet-mesh, ...
  std::string helpCall;  ///< "stvd distance MESH --help"
  std::string kind;      ///< " for a surface", or empty
};
/// The forms of every command that takes declared options, in the order
/// docs/cli.md documents them.
const std::vector<CommandForm>& commandForms();
const CommandForm& commandForm(OptionCommand command);

/// A command line read against the command's declarations.
struct CommandLine {
  std::string input;  ///< the one positional argument (empty when none)
  OptionValues values;
};

/// Reads argv[first..]: "--name value", "--name=value", switches, and one
/// positional INPUT (a second is a usage error); every value is checked by
/// its declaration as it is read. -h or --help prints help() and ends the
/// tool with kExitOk. An option the command does not take is a usage error,
/// "unknown option '--x' (see stvd path --help)", or for an option the
/// command refuses on purpose, its reason ("--domain-connectivity applies
/// to voxel grids only").
CommandLine readCommandLine(OptionCommand command, int argc, char** argv, int first,
                            const std::function<std::string()>& help);

}  // namespace stvd::tool

// The help and the documentation of the options, printed from their
// declarations (command_options.hpp): every default, range and list of
// choices comes from the declaration, so from the library's constants.
#pragma once

#include <initializer_list>
#include <string>

#include "command_options.hpp"

namespace stvd::tool {

/// The options of the groups that `command` takes, as its help lists them:
/// "  --k N                   STVD memory depth, 1..16 (default 6; see
/// docs/cli.md).", wrapped at 94 columns.
std::string optionHelp(OptionCommand command, std::initializer_list<OptionGroup> groups);

/// The title of a group in docs/cli.md ("Propagation").
std::string optionGroupTitle(OptionGroup group);

/// docs/cli.md's option tables of `command` (one per group it takes, or
/// only `groups` when not empty): "| option | default | meaning |".
std::string optionTables(OptionCommand command, const std::vector<OptionGroup>& groups = {});

/// `stvd help --markdown COMMAND [GROUP...]`: prints optionTables (groups
/// named as in optionGroupTitle, in lower case with dashes); exit code.
int printOptionTables(int argc, char** argv, int first);

}  // namespace stvd::tool

#include "option_help.hpp"

#include <algorithm>
#include <cctype>
#include <iostream>
#include <sstream>

namespace stvd::tool {
namespace {

constexpr std::size_t kHelpWidth = 94;
constexpr std::size_t kTextColumn = 26;

/// `text` in lines of at most `width` characters (a longer word gets a line
/// of its own).
std::vector<std::string> wrapped(const std::string& text, std::size_t width) {
  std::istringstream words(text);
  std::vector<std::string> lines;
  std::string line, word;
  while (words >> word) {
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  lines.push_back(line);
  return lines;
}

std::string flagsText(const OptionDeclaration& o) {
  std::string text = o.shortFlag.empty() ? o.flag : o.shortFlag + ", " + o.flag;
  return o.valueName.empty() ? text : text + " " + o.valueName;
}

/// One option as the help lists it: the flags in the first 24 columns
/// after two spaces, the text from column 26 (from the next line when the
/// flags are longer); each '\n' of the text starts a new line.
std::string optionEntry(const OptionDeclaration& o, OptionCommand command) {
  const std::string flags = flagsText(o);
  const bool ownLine = flags.size() + 2 >= kTextColumn;
  std::vector<std::string> lines;
  std::istringstream paragraphs(optionHelpText(o, command));
  for (std::string paragraph; std::getline(paragraphs, paragraph);) {
    const std::vector<std::string> more = wrapped(paragraph, kHelpWidth - kTextColumn);
    lines.insert(lines.end(), more.begin(), more.end());
  }
  std::string out = "  " + flags + (ownLine ? "\n" : std::string(kTextColumn - 2 - flags.size(), ' '));
  for (std::size_t i = 0; i < lines.size(); ++i)
    out += (i == 0 && !ownLine ? "" : std::string(kTextColumn, ' ')) + lines[i] + "\n";
  return out;
}

std::string markdownCell(std::string text) {
  for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at)) text.replace(at, 1, " ");
  for (std::size_t at = text.find('|'); at != std::string::npos; at = text.find('|', at + 2)) text.replace(at, 1, "\\|");
  return text;
}

std::string groupName(OptionGroup group) {
  std::string name;
  for (const char c : optionGroupTitle(group)) name += c == ' ' ? '-' : static_cast<char>(std::tolower(c));
  return name;
}

const OptionGroup kGroups[] = {OptionGroup::Seeds,         OptionGroup::Targets,    OptionGroup::Regions,
                               OptionGroup::Propagation,   OptionGroup::TensorFile, OptionGroup::Metric,
                               OptionGroup::FodFile,
                               OptionGroup::SurfaceMetric, OptionGroup::MeshMetric, OptionGroup::Paths,
                               OptionGroup::Output};

}  // namespace

std::string optionHelp(OptionCommand command, std::initializer_list<OptionGroup> groups) {
  std::string out;
  for (const OptionGroup group : groups)
    for (const OptionDeclaration& o : allOptionDeclarations())
      if (o.group == group && o.takes(command)) out += optionEntry(o, command);
  return out;
}

std::string optionGroupTitle(OptionGroup group) {
  switch (group) {
    case OptionGroup::Seeds: return "Seeds";
    case OptionGroup::Targets: return "Targets";
    case OptionGroup::Regions: return "Regions";
    case OptionGroup::Propagation: return "Propagation";
    case OptionGroup::TensorFile: return "Tensor file";
    case OptionGroup::Metric: return "Metric";
    case OptionGroup::FodFile: return "FOD file";
    case OptionGroup::SurfaceMetric: return "Surface metric";
    case OptionGroup::MeshMetric: return "Mesh metric";
    case OptionGroup::Paths: return "Paths";
    case OptionGroup::Output: return "Output";
  }
  return "?";
}

std::string optionTables(OptionCommand command, const std::vector<OptionGroup>& groups) {
  std::string out;
  for (const OptionGroup group : kGroups) {
    if (!groups.empty() && std::find(groups.begin(), groups.end(), group) == groups.end()) continue;
    std::string rows;
    for (const OptionDeclaration& o : allOptionDeclarations()) {
      if (o.group != group || !o.takes(command) || o.flag == "--help") continue;
      const std::string flags = o.shortFlag.empty() ? "`" + flagsText(o) + "`"
                                                    : "`" + o.shortFlag + "`, `" + o.flag +
                                                          (o.valueName.empty() ? "" : " " + o.valueName) + "`";
      const std::string byDefault = optionDefaultText(o, command);
      rows += "| " + flags + " | " + (byDefault.empty() ? "" : "`" + markdownCell(byDefault) + "`") + " | " +
              markdownCell(optionHelpText(o, command)) + " |\n";
    }
    if (rows.empty()) continue;
    out += (out.empty() ? "" : "\n") + optionGroupTitle(group) + ":\n\n| option | default | meaning |\n| --- | --- | --- |\n" +
           rows;
  }
  return out;
}

int printOptionTables(int argc, char** argv, int first) {
  if (first >= argc) usageError("help --markdown: name a command (distance, path, connectivity, surface, tet-mesh, info)");
  const std::string name = argv[first];
  const CommandForm* form = nullptr;
  for (const CommandForm& f : commandForms())
    if (f.name == name) form = &f;
  if (!form) usageError("help --markdown: no command '" + name + "' (distance, path, connectivity, surface, tet-mesh, info)");
  std::vector<OptionGroup> groups;
  for (int i = first + 1; i < argc; ++i) {
    bool known = false;
    for (const OptionGroup group : kGroups)
      if (groupName(group) == argv[i]) {
        groups.push_back(group);
        known = true;
      }
    if (!known) usageError("help --markdown: no group '" + std::string(argv[i]) + "'");
  }
  std::cout << optionTables(form->command, groups);
  return kExitOk;
}

}  // namespace stvd::tool

#include "stvd/front_end/option_declarations.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "stvd/errors.hpp"

namespace stvd {
namespace {

constexpr double kLargestInteger = 2147483647.0;
// Vertex numbers: any 64-bit integer a double holds exactly.
constexpr double kLargestIndex = 9007199254740992.0;

/// A choice's name as the front end writes it: "field:FILE" or "field".
std::string choiceName(const OptionChoice& choice, OptionNaming naming) {
  const std::size_t colon = choice.name.find(':');
  return naming == OptionNaming::Keywords && colon != std::string::npos ? choice.name.substr(0, colon) : choice.name;
}

std::string numberText(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (std::isnan(x)) return "nan";
  std::ostringstream s;
  s.precision(15);
  s << x;
  return s.str();
}

/// "a, b, c": the names the message lists.
std::string choiceList(const OptionDeclaration& o, OptionNaming naming) {
  std::string list;
  for (const OptionChoice& c : o.choices) list += (list.empty() ? "" : ", ") + choiceName(c, naming);
  return list;
}

[[noreturn]] void refuse(const std::string& message) { throw OptionError(message); }

/// The range's one message form per shape of range.
void checkRange(const OptionDeclaration& o, double x, const std::string& name) {
  const OptionRange& r = o.range;
  const bool belowMin = r.min && (r.minExcluded ? !(x > *r.min) : !(x >= *r.min));
  const bool aboveMax = r.max && (r.maxExcluded ? !(x < *r.max) : !(x <= *r.max));
  if (!belowMin && !aboveMax) return;
  const bool integral = o.type != OptionType::Number;
  if (r.min && r.max && integral) refuse(name + " must be between " + numberText(*r.min) + " and " + numberText(*r.max));
  if (r.min && r.max)
    refuse(name + " must be in " + (r.minExcluded ? "(" : "[") + numberText(*r.min) + ", " + numberText(*r.max) +
           (r.maxExcluded ? ")" : "]"));
  if (r.min && *r.min == 0.0 && r.minExcluded) refuse(name + " must be positive");
  if (r.min) refuse(name + " must be " + (r.minExcluded ? "above " : "at least ") + numberText(*r.min));
  refuse(name + " must be " + (r.maxExcluded ? "below " : "at most ") + numberText(*r.max));
}

double parseNumberText(const std::string& name, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x))
    refuse(name + ": '" + text + "' is not a number");
  return x;
}

long long parseIntegerText(const std::string& name, const std::string& text, double largest) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || std::abs(static_cast<double>(x)) > largest)
    refuse(name + ": '" + text + "' is not an integer");
  return x;
}

/// "A,B,C" (spaces allowed around the numbers).
std::array<double, 3> parseTripleText(const OptionDeclaration& o, const std::string& name, const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, ',')) {
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    while (!part.empty() && part.back() == ' ') part.pop_back();
    parts.push_back(part);
  }
  if (parts.size() != 3 || text.back() == ',')
    refuse(name + ": '" + text + "' is not three comma-separated numbers");
  std::array<double, 3> triple{};
  for (int c = 0; c < 3; ++c)
    triple[c] = o.type == OptionType::Voxel ? static_cast<double>(parseIntegerText(name, parts[c], kLargestInteger))
                                            : parseNumberText(name, parts[c]);
  return triple;
}

/// The accepted choice that `text` names (an alias gives its choice), or
/// none.
std::optional<std::string> choiceOf(const OptionDeclaration& o, const std::string& text, OptionNaming naming) {
  for (const OptionChoice& c : o.choices) {
    const std::string name = choiceName(c, naming);
    if (text == name) return text;
    const std::size_t colon = name.find(':');
    if (colon != std::string::npos && text.size() > colon + 1 && text.compare(0, colon + 1, name, 0, colon + 1) == 0)
      return text;
  }
  for (const auto& [alias, choice] : o.aliases)
    if (text == alias) return choice;
  return std::nullopt;
}

bool isDefaultChoice(const OptionDeclaration& o, OptionCommand command, const OptionChoice& c) {
  const auto* value = std::get_if<std::string>(&o.defaultFor(command));
  if (value) return *value == c.name;
  const auto* number = std::get_if<long long>(&o.defaultFor(command));
  return number && std::to_string(*number) == c.name;
}

std::string choicesText(const OptionDeclaration& o, OptionCommand command) {
  std::string text;
  for (std::size_t i = 0; i < o.choices.size(); ++i) {
    const OptionChoice& c = o.choices[i];
    const bool isDefault = isDefaultChoice(o, command, c);
    if (o.choiceLayout == ChoiceLayout::Lines) {
      text += (i ? ";\n" : "") + c.name + (isDefault ? " (default)" : "") + (c.help.empty() ? "" : ": " + c.help);
    } else {
      text += i == 0 ? "" : i + 1 == o.choices.size() ? " or " : ", ";
      text += c.name;
      if (isDefault && !c.help.empty()) text += " (default: " + c.help + ")";
      else if (isDefault) text += " (default)";
      else if (!c.help.empty()) text += " (" + c.help + ")";
    }
  }
  return text;
}

void replaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

}  // namespace

OptionDomain optionDomainOf(OptionCommand command) {
  switch (command) {
    case kSurfaceDistanceCommand: return OptionDomain::Surface;
    case kTetMeshDistanceCommand: return OptionDomain::TetMesh;
    default: return OptionDomain::VoxelGrid;
  }
}

const OptionDeclaration* findOption(const std::vector<OptionDeclaration>& table, const std::string& name) {
  for (const OptionDeclaration& o : table)
    if (o.flag == name || (!o.shortFlag.empty() && o.shortFlag == name) || (!o.keyword.empty() && o.keyword == name))
      return &o;
  return nullptr;
}

std::string optionName(const OptionDeclaration& o, OptionNaming naming) {
  return naming == OptionNaming::Keywords && !o.keyword.empty() ? o.keyword : o.flag;
}

std::string optionWithValue(const OptionDeclaration& o, const std::string& value, OptionNaming naming) {
  if (naming == OptionNaming::Flags || o.keyword.empty()) return o.flag + " " + value;
  const bool quoted = value != o.valueName && (o.type == OptionType::Choice || o.type == OptionType::Text) &&
                      !o.keywordTakesNumber;
  return o.keyword + "=" + (quoted ? "'" + value + "'" : value);
}

std::string optionSwitchedOn(const OptionDeclaration& o, OptionNaming naming) {
  if (naming == OptionNaming::Flags || o.keyword.empty()) return o.flag;
  return o.keyword + (o.keywordIsNegation ? "=False" : "=True");
}

std::string optionValueText(const OptionValue& value) {
  if (const auto* i = std::get_if<long long>(&value)) return std::to_string(*i);
  if (const auto* x = std::get_if<double>(&value)) return std::isinf(*x) ? "none" : numberText(*x);
  if (const auto* s = std::get_if<std::string>(&value)) return *s;
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const auto* p = std::get_if<std::array<double, 3>>(&value))
    return numberText((*p)[0]) + "," + numberText((*p)[1]) + "," + numberText((*p)[2]);
  return "";
}

std::string optionDefaultText(const OptionDeclaration& o, OptionCommand command) {
  if (!o.defaultText.empty()) return o.defaultText;
  return optionValueText(o.defaultFor(command));
}

std::string optionRangeText(const OptionDeclaration& o) {
  if (!o.range.min || !o.range.max || o.type == OptionType::Number) return "";
  return numberText(*o.range.min) + ".." + numberText(*o.range.max);
}

std::string optionHelpText(const OptionDeclaration& o, OptionCommand command) {
  std::string text = o.help;
  for (const auto& [commands, help] : o.helpFor)
    if (commands & command) {
      text = help;
      break;
    }
  replaceAll(text, "{choices}", choicesText(o, command));
  replaceAll(text, "{default}", optionDefaultText(o, command));
  replaceAll(text, "{range}", optionRangeText(o));
  return text;
}

OptionValue parseOptionText(const OptionDeclaration& o, const std::string& text, OptionNaming naming) {
  const std::string name = optionName(o, naming);
  switch (o.type) {
    case OptionType::Switch:
      return true;
    case OptionType::Integer:
      return checkOptionValue(o, parseIntegerText(name, text, kLargestInteger), naming);
    case OptionType::Index:
      return checkOptionValue(o, parseIntegerText(name, text, kLargestIndex), naming);
    case OptionType::Number: {
      if (o.acceptsNan && (text == "nan" || text == "NaN")) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        if (o.extraCheck) o.extraCheck(nan, name, text);
        return nan;
      }
      const double x = parseNumberText(name, text);
      checkRange(o, x, name);
      if (o.extraCheck) o.extraCheck(x, name, text);
      return x;
    }
    case OptionType::Point:
    case OptionType::Voxel:
      return parseTripleText(o, name, text);
    case OptionType::Choice:
    case OptionType::Text:
      return checkOptionValue(o, text, naming);
  }
  return {};
}

OptionValue checkOptionValue(const OptionDeclaration& o, OptionValue value, OptionNaming naming) {
  const std::string name = optionName(o, naming);
  switch (o.type) {
    case OptionType::Integer:
    case OptionType::Index:
      if (const auto* i = std::get_if<long long>(&value)) checkRange(o, static_cast<double>(*i), name);
      break;
    case OptionType::Number:
      if (const auto* i = std::get_if<long long>(&value)) value = static_cast<double>(*i);
      if (const auto* x = std::get_if<double>(&value)) {
        const bool nanAllowed = o.acceptsNan && std::isnan(*x);
        const bool infinityAllowed = o.keywordAcceptsInfinity && naming == OptionNaming::Keywords && *x > 0;
        if (!std::isfinite(*x) && !nanAllowed && !infinityAllowed)
          refuse(name + ": '" + numberText(*x) + "' is not a number");
        if (!nanAllowed) checkRange(o, *x, name);
        if (o.extraCheck) o.extraCheck(*x, name, numberText(*x));
      }
      break;
    case OptionType::Choice:
      if (const auto* s = std::get_if<std::string>(&value)) {
        const std::optional<std::string> choice = choiceOf(o, *s, naming);
        if (!choice) refuse(name + ": '" + *s + "' is not one of " + choiceList(o, naming));
        value = *choice;
      }
      break;
    default:
      break;
  }
  return value;
}

void OptionValues::set(const OptionDeclaration& option, OptionValue value) {
  setChecked(option, checkOptionValue(option, std::move(value), naming_));
}

void OptionValues::setChecked(const OptionDeclaration& option, OptionValue value) {
  std::vector<OptionValue>& values = values_[option.flag];
  if (!option.repeatable) values.clear();
  values.push_back(std::move(value));
}

const std::vector<OptionValue>& OptionValues::all(const std::string& flag) const {
  static const std::vector<OptionValue> none;
  const auto found = values_.find(flag);
  return found == values_.end() ? none : found->second;
}

std::optional<long long> OptionValues::integer(const std::string& flag) const {
  const auto& values = all(flag);
  if (values.empty()) return std::nullopt;
  if (const auto* i = std::get_if<long long>(&values.back())) return *i;
  throw std::logic_error(flag + " holds no integer");
}

std::optional<double> OptionValues::number(const std::string& flag) const {
  const auto& values = all(flag);
  if (values.empty()) return std::nullopt;
  if (const auto* x = std::get_if<double>(&values.back())) return *x;
  if (const auto* i = std::get_if<long long>(&values.back())) return static_cast<double>(*i);
  throw std::logic_error(flag + " holds no number");
}

std::optional<std::string> OptionValues::text(const std::string& flag) const {
  const auto& values = all(flag);
  if (values.empty()) return std::nullopt;
  if (const auto* s = std::get_if<std::string>(&values.back())) return *s;
  throw std::logic_error(flag + " holds no text");
}

}  // namespace stvd

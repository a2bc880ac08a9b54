// Options declared once. Every option of stvd's front ends (the command-line
// tool and the Python package) is one OptionDeclaration, written beside the
// algorithm it configures (propagation_choice_options.hpp,
// path_tracing_options.hpp, imaging/tensor_input_options.hpp, ...): its flag
// and its Python keyword, its group, its help, its default as a typed value
// read from the library's constant, its valid values, and the commands that
// take it. The tool parses its command lines, prints its help and writes
// docs/cli.md's option tables from these declarations; the package checks
// its keywords with them and builds stvd.defaults from them. So a default,
// a range or a message exists once, and the help cannot drift from the
// library.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace stvd {

/// The commands of the front ends, as bits of a set: which commands take an
/// option. Each has a counterpart in the Python package (in brackets).
enum OptionCommand : unsigned {
  kDistanceCommand = 1u << 0,         ///< stvd distance on a tensor volume (stvd.distance, stvd.propagate)
  kPathCommand = 1u << 1,             ///< stvd path (stvd.propagate, then stvd.trace_paths)
  kConnectivityCommand = 1u << 2,     ///< stvd connectivity (stvd.connectivity)
  kSurfaceDistanceCommand = 1u << 3,  ///< stvd distance MESH.obj|off|ply|stl (stvd.surface_distance)
  kTetMeshDistanceCommand = 1u << 4,  ///< stvd distance MESH.node (stvd.tet_mesh_distance)
  kInfoCommand = 1u << 5,             ///< stvd info
  kCohortCommand = 1u << 6,           ///< stvd cohort (stvd.cohort.run)
  kFodDistanceCommand = 1u << 7,      ///< stvd distance FOD --fod-basis (stvd.fod_distance): keywords only
};
using OptionCommands = unsigned;
inline constexpr OptionCommands kNoCommand = 0;
inline constexpr OptionCommands kVolumeCommands = kDistanceCommand | kPathCommand | kConnectivityCommand;
inline constexpr OptionCommands kMeshCommands = kSurfaceDistanceCommand | kTetMeshDistanceCommand;
inline constexpr OptionCommands kEveryCommand = kVolumeCommands | kMeshCommands | kInfoCommand | kCohortCommand;

/// The kind of domain a command runs on, where a default differs per kind
/// (STVD's k: defaultMemoryDepth<Domain>()).
enum class OptionDomain { VoxelGrid = 0, Surface = 1, TetMesh = 2 };
OptionDomain optionDomainOf(OptionCommand command);

/// What an option is about; the help and the documentation list options
/// group by group, in this order.
enum class OptionGroup {
  Seeds,
  Targets,
  Regions,
  Propagation,
  TensorFile,
  Metric,
  FodFile,
  SurfaceMetric,
  MeshMetric,
  Paths,
  Output,
};

/// The kind of value an option takes.
enum class OptionType {
  Switch,      ///< no value ("--lps")
  Integer,     ///< a 32-bit integer
  Index,       ///< a 64-bit integer (vertex numbers)
  Number,      ///< a finite number
  Choice,      ///< one of `choices` (or an alias)
  Text,        ///< any text, such as a file name
  Point,       ///< "X,Y,Z", three numbers
  Voxel,       ///< "I,J,K", three integers
};

/// A value as a front end holds it: none, a switch, an integer, a number,
/// a text or three numbers (a voxel's are integral).
using OptionValue = std::variant<std::monostate, bool, long long, double, std::string, std::array<double, 3>>;

/// How a front end writes options in its messages: the tool with its flags
/// ("--k must be between 1 and 16"), the Python package with its keywords
/// ("k must be between 1 and 16").
enum class OptionNaming { Flags, Keywords };

/// One accepted value of a Choice option. A name ending in ":FILE" accepts
/// any text after the colon on the command line (--metric field:FILE); the
/// Python keyword takes the name without it (metric='field').
struct OptionChoice {
  std::string name;
  std::string help;  ///< what it means; may be empty
};

/// Valid numbers of an Integer, Index or Number option; unset ends are open.
struct OptionRange {
  std::optional<double> min, max;
  bool minExcluded = false, maxExcluded = false;
};

/// How the help lists the choices of an option (`{choices}` in its help):
/// inline, "6, 18, 26 (default), 98 (5x5x5) or 290 (7x7x7)", or one per
/// line, "stvd (default): Short-Term Vector Dijkstra;".
enum class ChoiceLayout { Inline, Lines };

struct OptionDeclaration {
  std::string flag;          ///< "--k"
  std::string shortFlag;     ///< "-o", or empty
  std::string valueName;     ///< "N" in "--k N"; empty for a switch
  OptionType type = OptionType::Switch;
  OptionGroup group = OptionGroup::Output;
  /// The commands that take it.
  OptionCommands commands = kNoCommand;
  /// The Python keyword ("k"), or empty; which of the package's calls take
  /// it (those of `keywordCommands`, by default `commands`).
  std::string keyword;
  std::optional<OptionCommands> keywordCommands;
  /// A switch "--no-X" whose keyword X is true unless it is given
  /// (--no-memory-check, memory_check=True).
  bool keywordIsNegation = false;
  /// The keyword takes a number although the flag's choices are texts
  /// (domain_connectivity=18).
  bool keywordTakesNumber = false;
  /// The help, one text or one per command (the first whose commands
  /// include the command wins, then `help`). Placeholders: {default} (the
  /// default for the command's kind of domain), {range} ("1..16"),
  /// {choices} (the choices as `choiceLayout` says, the default marked).
  std::string help;
  std::vector<std::pair<OptionCommands, std::string>> helpFor;
  std::vector<OptionChoice> choices;
  ChoiceLayout choiceLayout = ChoiceLayout::Inline;
  /// Other accepted spellings of a choice: {"nifti", "lower"}.
  std::vector<std::pair<std::string, std::string>> aliases;
  OptionRange range;
  /// A Number option that takes "nan" too (--unreachable-value), and one
  /// whose Python keyword takes infinity, meaning no limit (max_distance).
  bool acceptsNan = false;
  bool keywordAcceptsInfinity = false;
  /// The default per kind of domain (OptionDomain), taken from the
  /// library's constants; none where it is std::monostate.
  std::array<OptionValue, 3> defaults;
  /// What the help says instead of a value when the default is not one
  /// ("the number of cores"); empty otherwise.
  std::string defaultText;
  bool repeatable = false;
  /// Commands that know the option only to refuse it with `refusal`
  /// ("applies to voxel grids only") instead of calling it unknown.
  OptionCommands refusedBy = kNoCommand;
  std::string refusal;
  /// A further rule on a checked value (the unreachable value must fit in a
  /// float32 map); throws OptionError in the front end's naming. `given`
  /// is the value as the user wrote it.
  void (*extraCheck)(const OptionValue& value, const std::string& name, const std::string& given) = nullptr;

  bool takes(OptionCommand command) const { return (commands & command) != 0; }
  bool hasKeywordFor(OptionCommand command) const {
    return !keyword.empty() && (keywordCommands.value_or(commands) & command) != 0;
  }
  const OptionValue& defaultFor(OptionCommand command) const {
    return defaults[static_cast<int>(optionDomainOf(command))];
  }
};

/// The declaration among `table` whose flag, short flag or keyword is
/// `name`; null when there is none.
const OptionDeclaration* findOption(const std::vector<OptionDeclaration>& table, const std::string& name);

/// "--k" or "k".
std::string optionName(const OptionDeclaration& option, OptionNaming naming);
/// An option with a value, for messages: "--method lanthier" or
/// "method='lanthier'" ("--steiner M" or "steiner=M" for a value name).
std::string optionWithValue(const OptionDeclaration& option, const std::string& value, OptionNaming naming);

/// A switch turned on, for messages: "--accept-implausible-tensors" or
/// "accept_implausible_tensors=True" ("memory_check=False" for a negation).
std::string optionSwitchedOn(const OptionDeclaration& option, OptionNaming naming);

/// A default (or any value) as the help and the docs print it: 6, 0.25,
/// -1, segment; "none" for an infinite number.
std::string optionValueText(const OptionValue& value);
/// The default of `option` for `command` as the help prints it, or its
/// defaultText; empty when it has none.
std::string optionDefaultText(const OptionDeclaration& option, OptionCommand command);
/// "1..16", or empty.
std::string optionRangeText(const OptionDeclaration& option);
/// The help of `option` for `command` with its placeholders filled; lines
/// of a ChoiceLayout::Lines list are separated by '\n'.
std::string optionHelpText(const OptionDeclaration& option, OptionCommand command);

/// The value of `text` as given on the command line to `option`, checked:
/// OptionError with one message form per problem ("--k: 'x' is not an
/// integer", "--k must be between 1 and 16", "--method: 'fast' is not one
/// of stvd, dijkstra, lanthier").
OptionValue parseOptionText(const OptionDeclaration& option, const std::string& text,
                            OptionNaming naming = OptionNaming::Flags);
/// The same checks on a typed value (as the Python package passes it;
/// a choice's alias becomes its name); OptionError in `naming`.
OptionValue checkOptionValue(const OptionDeclaration& option, OptionValue value, OptionNaming naming);

/// The options a front end was given, each checked as it is set, by flag.
/// The library's parts read theirs from it (propagationChoiceOf,
/// imaging::tensorInputOptionsOf, pathTracingOptionsOf), so the tool and
/// the package fill the same structs the same way.
class OptionValues {
 public:
  explicit OptionValues(OptionNaming naming = OptionNaming::Flags) : naming_(naming) {}
  OptionNaming naming() const { return naming_; }
  /// Checks `value` (checkOptionValue) and keeps it; a repeatable option
  /// keeps every value, any other its last.
  void set(const OptionDeclaration& option, OptionValue value);
  /// Keeps a value parseOptionText already checked.
  void setChecked(const OptionDeclaration& option, OptionValue value);
  bool has(const std::string& flag) const { return values_.count(flag) != 0; }
  /// Every value given to the option, in order.
  const std::vector<OptionValue>& all(const std::string& flag) const;
  std::optional<long long> integer(const std::string& flag) const;
  std::optional<double> number(const std::string& flag) const;
  std::optional<std::string> text(const std::string& flag) const;

 private:
  OptionNaming naming_;
  std::map<std::string, std::vector<OptionValue>> values_;
};

}  // namespace stvd

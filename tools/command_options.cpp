#include "command_options.hpp"

#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/tetmesh/tet_mesh_options.hpp"

namespace stvd::tool {
namespace {

OptionDeclaration outputOption(const std::string& flag, const std::string& valueName, OptionCommands commands,
                               const std::string& help) {
  OptionDeclaration o;
  o.flag = flag;
  o.valueName = valueName;
  o.type = valueName.empty() ? OptionType::Switch : OptionType::Text;
  o.group = OptionGroup::Output;
  o.commands = commands;
  o.help = help;
  return o;
}

/// The tool's own options: where the results go, and --help.
std::vector<OptionDeclaration> toolDeclarations() {
  std::vector<OptionDeclaration> table;
  OptionDeclaration output = outputOption(
      "--output", "FILE", kVolumeCommands | kMeshCommands,
      "the distance map (required): .nii, .nii.gz, .nrrd (gzip-compressed), .nhdr (with the data file "
      "<base>.raw.gz), .mif, .mif.gz (MRtrix) or .vdb (OpenVDB).\nIts folder must exist; it must not be an input. "
      "Written with the statistics into a staging folder next to it and moved into place when both are complete.");
  output.shortFlag = "-o";
  output.helpFor = {
      {kPathCommand,
       "the paths (required), by extension: .tck (MRtrix), .trk (TrackVis) or .vtk (legacy VTK polydata); "
       "coordinates are RAS millimetres. Per path: geodesic_mm (the distance value at the target), euclidean_mm "
       "(length of the polyline) and mean_fa (diffusion tensors only) as per-streamline values (.trk properties, "
       ".vtk cell data, .tck header entries), and FA per point (.trk scalars, .vtk point data)."},
      {kConnectivityCommand,
       "the table (required). The table and matrices appear together, complete, or not at all; none may be an "
       "input."},
      {kSurfaceDistanceCommand,
       ".ply (binary: the mesh, its coordinates in the input's type, with a float vertex property distance; "
       "unreached inf),\n.vtk (legacy POLYDATA, POINT_DATA distance; unreached -1) or\n.csv (rows "
       "vertex,distance; unreached inf),\n.shape.gii or .func.gii (GIfTI, float32; unreached NaN) or a FreeSurfer "
       "curv file (.curv, lh.NAME, rh.NAME; float32, unreached NaN). It must not be an input; written with the "
       "statistics into a staging folder next to it and moved into place when both are complete."},
      {kTetMeshDistanceCommand,
       ".vtk (legacy VTK), .vtu (VTK XML) or .csv (vertex,distance with the input's vertex numbers). VTK files "
       "hold the mesh with the point arrays \"distance\" and \"vertex_number\". Written atomically.\nOr .nii, "
       ".nii.gz, .nrrd, .nhdr, .mif with --reference: the distance resampled onto the reference's grid (float32; "
       "linear inside each tetrahedron; voxels outside the mesh hold the unreachable value)."}};
  table.push_back(output);
  table.push_back(outputOption("--tsv", "FILE", kPathCommand,
                               "the per-path summary table (default: FILE with the extension replaced by .tsv)."));
  table.push_back(outputOption(
      "--matrix", "FILE.csv", kConnectivityCommand,
      "also the square N x N matrix of geodesic distances (mm): row A, column B holds d(A, B); rows and columns in "
      "label order, the labels in a '# labels:' header line; nan (no value) on the diagonal and where B is not "
      "reachable from A, as n/a in the table and NaN in Python (numpy.loadtxt(FILE, delimiter=',') and MRtrix's "
      "matrix readers skip the '#' lines, as for tck2connectome output)."));
  table.push_back(outputOption("--matrix-index", "FILE.csv", kConnectivityCommand,
                               "the same matrix of the connectivity index; nan on the diagonal and where B is not "
                               "reachable."));
  table.push_back(outputOption(
      "--region-matrix", "FILE.csv", kSurfaceDistanceCommand,
      "with --seeds REGIONS (.annot, .label.gii): the matrix of geodesic distances between the regions (those "
      "of --seed-region, else every named region with vertices), one propagation per region on --threads: row A, "
      "column B the shortest distance from A to a vertex of B, the region names in a '# labels:' header line, 0 on "
      "the diagonal, inf where B is not reached. -o then holds each vertex's distance to its nearest region."));
  table.push_back(outputOption(
      "--region-maps", "PATTERN", kSurfaceDistanceCommand,
      "with --seeds REGIONS: one distance map per region (the regions as for --region-matrix), each written to "
      "PATTERN with {region} replaced by the region's name (letters, digits, '-', '_' and '.' kept, others '_'): "
      ".shape.gii, .func.gii or FreeSurfer curv. The surface and metric are built once; the regions run in "
      "parallel (--threads)."));
  table.push_back(outputOption(
      "--nearest-region", "FILE", kSurfaceDistanceCommand,
      "with --seeds REGIONS: the key of each vertex's nearest region (.shape.gii, .func.gii or FreeSurfer curv; -1 "
      "where no region reaches), the regions as for --region-matrix; -o then holds the distance to it."));
  OptionDeclaration stats =
      outputOption("--stats", "FILE.json", kVolumeCommands | kSurfaceDistanceCommand,
                   "parameters, counts, seconds per phase and peak memory as JSON.");
  stats.helpFor = {
      {kPathCommand | kConnectivityCommand, "parameters, counts and seconds as JSON (as stvd distance writes)."},
      {kSurfaceDistanceCommand, "parameters, mesh counts, seeds, distances, seconds and peak memory."}};
  table.push_back(stats);
  OptionDeclaration report = outputOption(
      "--report", "FILE.html", kVolumeCommands,
      "a self-contained QC page: slices of the map over FA through the seed, the statistics and the warnings "
      "(Python 3 and matplotlib, checked before any output is written; docs/report.md).");
  report.helpFor = {{kPathCommand,
                     "a self-contained QC page: the paths over the distance map and FA, their figures, the "
                     "statistics and the warnings (Python 3 and matplotlib, checked before any output is written; docs/report.md)."},
                    {kConnectivityCommand,
                     "a self-contained QC page: the regions over FA, the matrices as heat maps, the statistics and "
                     "the warnings (Python 3 and matplotlib, checked before any output is written; docs/report.md)."}};
  table.push_back(report);
  table.push_back(outputOption(
      "--subject", "NAME", kVolumeCommands,
      "with --report: the name in the page's title and in a cohort index (default: the input's file name without "
      "its extension; any text, shown as text)."));
  OptionDeclaration voxel = outputOption(
      "--voxel", "I,J,K", kInfoCommand,
      "also describe this voxel (stvd's 0-based index, as the file stores it): the index MRtrix shows for it and "
      "its RAS position.");
  voxel.type = OptionType::Voxel;
  voxel.repeatable = true;
  table.push_back(voxel);
  OptionDeclaration quiet =
      outputOption("--quiet", "", kVolumeCommands | kMeshCommands, "no summary on stdout.");
  quiet.shortFlag = "-q";
  quiet.helpFor = {{kDistanceCommand, "no summary on stdout, no progress bar."}};
  table.push_back(quiet);
  OptionDeclaration help = outputOption("--help", "", kVolumeCommands | kMeshCommands | kInfoCommand, "this text.");
  help.shortFlag = "-h";
  table.push_back(help);
  return table;
}

/// The order in which the help lists the options within a group.
const char* const kHelpOrder[] = {
    "--seed-voxel", "--seed-vertex", "--seed-point", "--seed-at", "--lps", "--seeds", "--target-voxel",
    "--target-point", "--targets", "--labels", "--threads", "--method", "--steiner", "--k", "--chain-measure",
    "--stencil", "--domain-connectivity", "--max-distance", "--no-memory-check", "--tensor-order",
    "--tensor-frame", "--mask", "--tensor-kind", "--diffusion-metric", "--max-anisotropy", "--fa-threshold",
    "--accept-implausible-tensors", "--accept-misaligned-tensors", "--fod-basis", "--fod-frame", "--fod-floor",
    "--fod-power", "--metric", "--anisotropy", "--tensors",
    "--tensor-attribute", "--outside-image", "--step", "--smooth", "--no-refine", "--discrete", "--output", "--reference",
    "--tsv", "--matrix", "--matrix-index", "--region-matrix", "--region-maps", "--nearest-region",
    "--unreachable-value", "--stats", "--report", "--subject", "--voxel", "--quiet", "--help"};

std::vector<OptionDeclaration> allDeclarations() {
  std::vector<OptionDeclaration> all;
  for (const auto* table :
       {&imaging::seedOptionDeclarations(), &meshOptionDeclarations(), &regionConnectivityOptionDeclarations(),
        &propagationOptionDeclarations(), &imaging::tensorInputOptionDeclarations(),
        &imaging::fodInputOptionDeclarations(),
        &tetmesh::tetMeshOptionDeclarations(), &pathTracingOptionDeclarations()})
    all.insert(all.end(), table->begin(), table->end());
  const std::vector<OptionDeclaration> own = toolDeclarations();
  all.insert(all.end(), own.begin(), own.end());
  const auto rank = [](const OptionDeclaration& o) {
    const auto end = std::end(kHelpOrder);
    return std::find_if(std::begin(kHelpOrder), end, [&](const char* flag) { return o.flag == flag; }) -
           std::begin(kHelpOrder);
  };
  std::stable_sort(all.begin(), all.end(), [&](const OptionDeclaration& a, const OptionDeclaration& b) {
    return a.group != b.group ? a.group < b.group : rank(a) < rank(b);
  });
  return all;
}

/// "unknown option '--x' (see stvd path --help)", or the command's reason
/// to refuse a declared option.
[[noreturn]] void refuseOption(const CommandForm& form, const std::string& given) {
  for (const OptionDeclaration& o : allOptionDeclarations())
    if ((o.flag == given || o.shortFlag == given) && (o.refusedBy & form.command))
      usageError(o.flag + " " + o.refusal);
  usageError("unknown option '" + given + "'" + form.kind + " (see " + form.helpCall + ")");
}

}  // namespace

const std::vector<OptionDeclaration>& allOptionDeclarations() {
  static const std::vector<OptionDeclaration> all = allDeclarations();
  return all;
}

const OptionDeclaration& toolOption(const std::string& name) {
  const OptionDeclaration* option = findOption(allOptionDeclarations(), name);
  if (!option) throw std::logic_error("no option " + name);
  return *option;
}

const std::vector<CommandForm>& commandForms() {
  static const std::vector<CommandForm> forms{
      {kDistanceCommand, "distance", "stvd distance --help", ""},
      {kPathCommand, "path", "stvd path --help", ""},
      {kConnectivityCommand, "connectivity", "stvd connectivity --help", ""},
      {kSurfaceDistanceCommand, "surface", "stvd distance MESH --help", " for a surface"},
      {kTetMeshDistanceCommand, "tet-mesh", "stvd distance MESH.node --help", " for a tetrahedral mesh"},
      {kInfoCommand, "info", "stvd info --help", ""},
  };
  return forms;
}

const CommandForm& commandForm(OptionCommand command) {
  for (const CommandForm& form : commandForms())
    if (form.command == command) return form;
  throw std::logic_error("no command form");
}

CommandLine readCommandLine(OptionCommand command, int argc, char** argv, int first,
                            const std::function<std::string()>& help) {
  const CommandForm& form = commandForm(command);
  CommandLine line;
  ArgumentReader args(argc, argv, first);
  while (!args.done()) {
    const std::string given = args.take();
    if (!args.isOption(given)) {
      if (!line.input.empty()) usageError("more than one input file: '" + line.input + "' and '" + given + "'");
      line.input = given;
      continue;
    }
    const OptionDeclaration* option = findOption(allOptionDeclarations(), given);
    if (!option || !option->takes(command) || given == option->keyword) refuseOption(form, given);
    if (option->flag == "--help") {
      args.noValue(given);
      std::cout << help();
      throw ToolError(kExitOk, "");
    }
    if (option->type == OptionType::Switch) {
      args.noValue(given);
      line.values.setChecked(*option, true);
    } else {
      line.values.setChecked(*option, parseOptionText(*option, args.value(given)));
    }
  }
  return line;
}

}  // namespace stvd::tool

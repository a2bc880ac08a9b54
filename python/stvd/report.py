"""Visual quality-control reports: one self-contained HTML page per run of
``stvd distance``, ``stvd path`` or ``stvd connectivity`` (or of the same
calls from Python), and a cohort index page over many of them.

A run page shows axial, coronal and sagittal slices through the seed of the
distance map over FA (computed from the tensors when no FA image is given;
for FOD runs the FOD's GFA)
with the seeds marked and the paths projected, the connectivity matrix as a
heat map, the run's statistics with the stvd version and command line, and
the warnings a reviewer must see. Slices are shown in a stated convention
(neurological by default) with L/R/A/P/S/I letters from the image's direction
cosines. Images are embedded as data URIs; nothing is fetched.

Entry points:

- ``write_report(output, result, ...)``: from Python objects
  (``stvd.Propagation``, ``stvd.Paths``, ``stvd.Connectivity``, and those of
  FOD runs: the image of ``stvd.fod_distance``, ``stvd.fod_paths``,
  ``stvd.fod_connectivity``);
- ``write_run_report(output, statistics, ...)``: from the files of a tool run
  (its ``--stats`` JSON and outputs); ``stvd report`` and ``--report`` call it;
- ``write_cohort_index(output, subjects)`` and ``cohort_index_from_folder``:
  the cohort index;
- ``python3 -m stvd.report``: the command line behind ``stvd report``.

See docs/report.md.
"""

import argparse
import csv
import datetime
import errno
import io
import json
import math
import os
import sys
import time

import numpy as np

from . import __version__
from ._files import PAGE_BYTES, RECORD_BYTES, TABLE_BYTES, read_regular_text, require_regular_file
from ._inputs import is_image, is_path, tensor_field
from ._outputs import FileConflictError, OutputError, OutputFiles
from . import _report_page as page
from ._report_slices import (CONVENTIONS, PLANES, SEED_COLOUR, TARGET_COLOUR, DisplayGrid, Panel, contour_step,
                             draw_panel)

__all__ = ["write_report", "write_run_report", "write_cohort_index", "cohort_index_from_folder",
           "cohort_entries_from_folder", "ReportError", "CONVENTIONS", "main"]

# Exit codes of docs/cli.md.
EXIT_INTERNAL, EXIT_USAGE, EXIT_INPUT, EXIT_OUTPUT = 1, 2, 3, 5


class ReportError(Exception):
    """A report that cannot be made: ``str(error)`` is the one-line message
    (naming the file), ``exit_code`` the tool's exit code for it."""

    def __init__(self, message, exit_code=EXIT_INPUT):
        super().__init__(message)
        self.exit_code = exit_code


# ---------------------------------------------------------------------------
# What a page shows


class _RunContent:
    """What a run page shows, gathered from files or from Python objects."""

    def __init__(self, kind, statistics, affine, shape, fa, fa_source):
        self.kind = kind                    # distance, path or connectivity
        self.statistics = statistics        # the --stats record (dict)
        self.affine = np.asarray(affine, dtype=np.float64)
        self.shape = tuple(int(n) for n in shape[:3])
        self.fa = fa                        # on the tensors' grid
        self.fa_source = fa_source
        self.fa_name = "FA"                 # GFA for FOD runs (docs/fod.md), unless an FA image is given
        self.distance = None                # float, NaN where not reached
        self.seeds = np.zeros((0, 3), np.int64)  # voxel indices
        self.seed_region = None             # bool array of label seeds
        self.target_region = None           # bool array of label targets (path runs)
        self.paths = []                     # (N, 3) RAS millimetres
        self.path_rows = []                 # per-path figures (dicts)
        self.connectivity = None            # dict: labels, geodesic_mm, connectivity
        self.regions = None                 # label array of connectivity runs
        self.notes = []                     # what the reviewer should know besides warnings


class _SliceLayers:
    """The arrays and overlays of the slices, on the turned grid."""

    def __init__(self, content, grid):
        import matplotlib

        self.fa = grid.turn(np.nan_to_num(content.fa, nan=0.0))
        self.distance = grid.turn(content.distance) if content.distance is not None else None
        finite = self.distance[np.isfinite(self.distance)] if self.distance is not None else np.zeros(0)
        self.distance_max = float(finite.max()) if finite.size else 1.0
        self.contour_step = contour_step(self.distance_max) if finite.size else None
        self.regions = None
        self.region_colours = []
        if content.regions is not None:
            values = np.unique(content.regions[content.regions != 0])
            rank = np.zeros(content.regions.shape, np.int32)
            for n, value in enumerate(values, start=1):
                rank[content.regions == value] = n
            self.regions = grid.turn(rank)
            palette = matplotlib.colormaps["tab20"].colors
            self.region_colours = [matplotlib.colors.to_hex(palette[n % len(palette)]) for n in range(len(values) + 1)]
        self.seed_region = grid.turn(content.seed_region) if content.seed_region is not None else None
        self.target_region = grid.turn(content.target_region) if content.target_region is not None else None
        self.seeds = grid.index_of_voxels(content.seeds) if len(content.seeds) else np.zeros((0, 3), np.int64)
        self.paths = [grid.index_of_points(points) for points in content.paths]
        self.path_colours = path_colours(len(content.paths))


def path_colours(count):
    """The colour of each path, by its order (tab10, repeating)."""
    import matplotlib

    palette = matplotlib.colormaps["tab10"].colors
    return [matplotlib.colors.to_hex(palette[n % len(palette)]) for n in range(count)]


def _centre_voxel(content):
    """The voxel the three slices go through: the seed (the seed voxel
    nearest to the seeds' centre when there are several), or for
    connectivity the region voxel nearest to the regions' centre."""
    if len(content.seeds):
        voxels = content.seeds
    elif content.regions is not None and np.any(content.regions):
        voxels = np.argwhere(content.regions != 0)
    elif content.seed_region is not None and np.any(content.seed_region):
        voxels = np.argwhere(content.seed_region)
    else:
        return np.array(content.shape) // 2
    centre = voxels.mean(axis=0)
    return voxels[np.argmin(((voxels - centre) ** 2).sum(axis=1))]


# ---------------------------------------------------------------------------
# Warnings and key figures


def _count(value):
    return int(value) if value is not None else 0


# Repairs of up to this share of the domain are routine: a good fit of a
# brain has well under 1 % of its tensors ill-conditioned (fitting noise in
# CSF and at the brain's edge; 0.66 % in the shipped brain). More is worth a
# reviewer's look (docs/report.md, "Warnings and notes").
ROUTINE_REPAIR_SHARE = 0.01


def reviewer_warnings(content):
    """The warnings of a run (what a reviewer must look at: the page's
    status is "warnings" when there is one) and the notes (information:
    how the tensors were read, routine repairs, what the run was asked to
    leave out), as two lists of one-line texts."""
    s = content.statistics
    warnings, notes = [], list(content.notes)
    voxels = s.get("voxels", {})
    parameters = s.get("parameters", {})
    repaired = _count(voxels.get("repaired"))
    if repaired:
        domain_voxels = _count(voxels.get("domain"))
        share = repaired / domain_voxels if domain_voxels else 1.0
        text = (f"{repaired:,} of {domain_voxels:,} domain voxels ({100.0 * share:.2f} %) had their tensors repaired "
                f"({_count(voxels.get('repaired_non_positive')):,} with a non-positive eigenvalue, "
                f"{_count(voxels.get('repaired_anisotropy')):,} beyond the eigenvalue-ratio cap of "
                f"{_cap_text(parameters.get('max_anisotropy'))})")
        if share <= ROUTINE_REPAIR_SHARE:
            notes.append(text + f": routine (at most {100 * ROUTINE_REPAIR_SHARE:g} % of the domain).")
        else:
            warnings.append(text + f": more than the {100 * ROUTINE_REPAIR_SHARE:g} % a good fit has; check the fit "
                                   "and how the tensors were read.")
    if _count(voxels.get("no_positive_eigenvalue")):
        warnings.append(f"{_count(voxels['no_positive_eigenvalue']):,} voxels have no positive eigenvalue and are "
                        "outside the domain.")
    if _count(s.get("label_seeds_left_out")):
        warnings.append(f"{_count(s['label_seeds_left_out']):,} seed label voxels lie outside the domain and were "
                        "left out.")
    propagation = s.get("propagation", {})
    reached, domain = propagation.get("finalized_vertices"), propagation.get("domain_vertices")
    if reached is not None and domain and reached < domain:
        text = f"{domain - reached:,} of {domain:,} domain voxels ({100.0 * (domain - reached) / domain:.1f} %) were not reached"
        if propagation.get("termination") == "max_distance_reached":
            notes.append(text + " (the propagation stopped at --max-distance): the run's own limit.")
        else:
            warnings.append(text + " (they are not connected to the seeds).")
    for row in content.path_rows:
        if row.get("fallbacks") not in (None, "", "none"):
            warnings.append(f"Path {row['path']} (to {row['target']}) fell back to the discrete path: "
                            f"{row['fallbacks']}.")
    if content.connectivity is not None:
        matrix = content.connectivity["geodesic_mm"]
        n = len(content.connectivity["labels"])
        missing = int(np.sum(~np.isfinite(matrix))) - n
        if missing:
            warnings.append(f"{missing} of {n * (n - 1)} ordered region pairs are not connected (n/a in the table).")
    regions = s.get("regions", {})
    if _count(regions.get("left_out")):
        warnings.append(f"{_count(regions['left_out'])} labelled regions have no voxel in the domain and were left "
                        "out.")
    if parameters.get("metric") == "fod":
        notes.insert(0, fod_metric_note(parameters))
    layout, order, frame = (parameters.get("tensor_layout"), parameters.get("tensor_order"),
                            parameters.get("tensor_frame"))
    if layout or order or frame:
        stated = parameters.get("tensor_frame_stated")
        how = "" if stated is None else (" (stated)" if stated else " (the default for this layout: check it)")
        if order is None and "3, 3" in str(layout):
            order_text = "none (3x3 matrices)"
        else:
            order_stated = parameters.get("tensor_order_stated")
            order_text = (order or "?") + ("" if order_stated is None else " (stated)" if order_stated else
                                           " (from the layout)")
        cap = ""
        if "max_anisotropy" in parameters:
            cap = f"; eigenvalue-ratio cap {_cap_text(parameters['max_anisotropy'])}"
        notes.insert(0, f"Tensors read as {layout or '?'}, component order {order_text}, in the {frame or '?'} "
                        f"frame{how}; metric {parameters.get('metric_formula', '?')}{cap}.")
    return warnings, notes


_METHOD_NAMES = {"stvd": "STVD", "dijkstra": "Dijkstra", "lanthier": "Lanthier"}


def fod_metric_note(parameters):
    """What an FOD run's metric was (docs/fod.md): basis (as given), frame,
    lmax, the cost's floor and power, the convexified norm as the run
    tabulated it, and the method."""
    basis, given = parameters.get("fod_basis", "?"), parameters.get("fod_basis_given")
    stated = parameters.get("fod_frame_stated")
    frame_how = "" if stated is None else (" (stated)" if stated else " (the default for this basis and format)")
    norm = str(parameters.get("fod_norm") or "convexified F* along the 26 neighbour directions")
    where = norm[len("convexified F* "):] if norm.startswith("convexified F* ") else norm
    method = parameters.get("method")

    def number(key):  # 2 and 2.0 alike: a JSON file writes the one, Python the other
        value = parameters.get(key, "?")
        return f"{value:g}" if isinstance(value, (int, float)) and not isinstance(value, bool) else str(value)

    return (f"FOD image read in the basis {basis}" + (f" (given as {given})" if given and given != basis else "") +
            f", in the {parameters.get('fod_frame', '?')} frame{frame_how}, lmax {parameters.get('fod_lmax', '?')}; "
            f"metric: the convexified FOD norm F* (floor {number('fod_floor')}, power {number('fod_power')}, "
            f"{parameters.get('fod_directions', '?')} sampling directions) "
            f"{where}, {_METHOD_NAMES.get(method, method or 'Dijkstra')} (docs/fod.md).")


def _cap_text(cap):
    """The eigenvalue-ratio cap as a run had it: a number, or none (metric
    tensors are taken as given; the tool's statistics write NaN, JSON null)."""
    if cap is None or (isinstance(cap, float) and cap != cap):
        return "none (tensors taken as given)"
    return page.number_text(float(cap), 0)


def key_figures(content):
    """The figures a cohort table shows for a run."""
    s = content.statistics
    figures = {}
    voxels, propagation, distance = s.get("voxels", {}), s.get("propagation", {}), s.get("distance_mm", {})
    if "domain" in voxels:
        figures["domain_voxels"] = _count(voxels["domain"])
        figures["repaired_voxels"] = _count(voxels.get("repaired"))
    if propagation.get("domain_vertices"):
        figures["reached_percent"] = round(100.0 * propagation["finalized_vertices"] / propagation["domain_vertices"],
                                           2)
    if distance.get("max") is not None:
        figures["max_distance_mm"] = round(float(distance["max"]), 2)
        figures["median_distance_mm"] = round(float(distance["median"]), 2)
    if content.kind == "path":
        figures["paths"] = len(content.path_rows)
    if content.connectivity is not None:
        figures["regions"] = len(content.connectivity["labels"])
    seconds = s.get("seconds", {}).get("total")
    if seconds is not None:
        figures["seconds"] = round(float(seconds), 2)
    return figures


# ---------------------------------------------------------------------------
# The page


_FIGURE_LABELS = {
    "domain_voxels": "domain voxels", "repaired_voxels": "repaired voxels", "reached_percent": "reached %",
    "max_distance_mm": "max distance (mm)", "median_distance_mm": "median distance (mm)", "paths": "paths",
    "regions": "regions", "seconds": "seconds",
}


def _statistics_rows(statistics, prefix=""):
    """The statistics record flattened into (key, value text) rows."""
    rows = []
    for key, value in statistics.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            rows.extend(_statistics_rows(value, name + "."))
        elif isinstance(value, list):
            text = json.dumps(value[:10])
            rows.append((name, text + (f" ... ({len(value)} in all)" if len(value) > 10 else "")))
        elif isinstance(value, float):
            rows.append((name, f"{value:.6g}"))
        else:
            rows.append((name, "null" if value is None else str(value)))
    return rows


def _render(content, subject, convention):
    """The page's HTML and its summary."""
    grid = DisplayGrid(content.affine, content.shape)
    layers = _SliceLayers(content, grid)
    centre = grid.index_of_voxels(_centre_voxel(content))[0]
    panels = [Panel(grid, plane, centre, convention) for plane in PLANES]
    pictures = [draw_panel(panel, layers) for panel in panels]
    thumbnail = draw_panel(panels[0], layers, scale=0.4)

    warnings, notes = reviewer_warnings(content)
    status = "warnings" if warnings else "ok"
    figures = key_figures(content)
    s = content.statistics
    title = f"stvd {content.kind}: {subject}"
    body = [f"<h1>{page.escape(title)} {page.status_badge(status)}</h1>",
            f"<p>Input <code>{page.escape(s.get('input', '?'))}</code>; stvd {page.escape(s.get('stvd_version', '?'))}; "
            f"report made {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}.</p>",
            f"<p>Command line: <code id=\"stvd-command-line\">{page.escape(s.get('command_line', '?'))}</code></p>"]
    if warnings:
        body.append("<h2>Warnings</h2>" + page.item_list(warnings, "warnings", "stvd-warnings"))
    body.append(page.item_list(notes, "notes", "stvd-notes"))

    # The slices.
    oblique = grid.obliquity_degrees()
    orientation = (f"Slices in <b id=\"stvd-convention\" data-convention=\"{convention}\">{convention}</b> convention: "
                   f"{page.escape(CONVENTIONS[convention])} (sagittal slices: anterior on the left). Edge letters "
                   f"from the image's direction cosines: orientation {grid.orientation_code()}")
    if oblique >= 0.05:
        orientation += f", oblique by {oblique:.1f} degrees (each slice is the voxel plane nearest to it)"
    orientation += "."
    source_voxel = _centre_voxel(content)
    background = content.fa_name  # FA, or an FOD run's GFA (docs/fod.md)
    what = f"distance map over {background}" if content.distance is not None else background
    body.append(f"<h2>Slices through voxel ({', '.join(str(int(c)) for c in source_voxel)}): {what}</h2>")
    body.append(f"<p>{orientation} {page.escape(background[0].upper() + background[1:])}: "
                f"{page.escape(content.fa_source)}.</p>")
    legend = []
    if content.distance is not None:
        import matplotlib

        viridis = matplotlib.colormaps["viridis"]
        stops = [matplotlib.colors.to_hex(viridis(x)) for x in np.linspace(0, 1, 9)]
        legend.append("Distance " + page.colour_bar(stops, "0", f"{layers.distance_max:.1f}", "mm") +
                      (f"; white contours every {layers.contour_step:g} mm" if layers.contour_step else "") +
                      f"; not reached: {background} only.")
    if len(content.seeds) or content.seed_region is not None:
        legend.append(f"Seeds: <span class=\"swatch\" style=\"background:{page.escape(SEED_COLOUR)}\"></span> magenta "
                      "ring (the seed voxels in the slice) and outline (label seeds).")
    if content.target_region is not None:
        legend.append(f"Targets: <span class=\"swatch\" style=\"background:{page.escape(TARGET_COLOUR)}\"></span> "
                      "cyan outline (the target label regions in the slice).")
    if content.paths:
        legend.append("Paths: projected onto each slice, coloured by their order (table below); a dot marks the "
                      "target end.")
    if content.regions is not None:
        legend.append("Regions: the labelled regions in the slice, coloured by label (heat map below).")
    body.append("<p>" + "<br>".join(legend) + "</p>")
    body.append("<div class=\"panels\">" + "".join(
        page.slice_figure(panel, picture, panel.caption()) for panel, picture in zip(panels, pictures)) + "</div>")

    if content.path_rows:
        rows = []
        for row, colour in zip(content.path_rows, layers.path_colours):
            rows.append([f"<span class=\"swatch\" style=\"background:{colour}\"></span> {page.escape(row['path'])}",
                         row["target"], row["geodesic_mm"], row["euclidean_mm"], row["mean_fa"], row["fallbacks"]])
        body.append("<h2>Geodesic paths</h2>" + page.table(
            ["path", "target", "geodesic (mm)", "length (mm)", "mean FA", "fallbacks"], rows, "stvd-paths",
            raw_columns=(0,)))

    if content.connectivity is not None:
        from ._report_matrix import draw_heatmap

        c = content.connectivity
        labels = [str(label) for label in c["labels"]]
        maps = [draw_heatmap(c["geodesic_mm"], labels, "geodesic distance d(a, b)", "magma_r", "mm"),
                draw_heatmap(c["connectivity"], labels, "connectivity index (path length / geodesic)", "viridis",
                             "index")]
        body.append("<h2>Connectivity</h2><div class=\"panels\">" + "".join(
            f"<img src=\"{page.data_uri(png)}\" alt=\"{page.escape(name)} heat map\">"
            for png, name in zip(maps, ["geodesic distance", "connectivity index"])) + "</div>")

    body.append("<h2>Statistics and parameters</h2>" +
                page.key_value_table(_statistics_rows(s), "stvd-statistics"))
    summary = {"subject": subject, "kind": content.kind, "status": status, "warnings": len(warnings),
               "figures": figures, "thumbnail": page.data_uri(thumbnail), "input": s.get("input"),
               "stvd_version": s.get("stvd_version")}
    body.append(page.summary_block(summary))
    return page.page(title, "\n".join(body)), summary


# ---------------------------------------------------------------------------
# From the files of a tool run


def _resolve(path, statistics_folder):
    """A path recorded in a statistics file: as given (relative to the
    current folder), or else relative to the statistics file's folder."""
    if not path:
        return None
    if os.path.isabs(path) or os.path.exists(path) or statistics_folder is None:
        return path
    beside = os.path.join(statistics_folder, path)
    return beside if os.path.exists(beside) else path


def _require_regular(path, role):
    """ReportError unless ``path`` is a regular file (a FIFO or a device
    named like an input is not read: it would block or never end)."""
    try:
        require_regular_file(path)
    except OSError as error:
        if error.errno == errno.ENOENT:
            raise ReportError(f"{path}: the {role} file does not exist") from None
        raise ReportError(f"{path}: cannot read the {role}: {getattr(error, 'reason', None) or error}") from None


def _load_nifti(path, role):
    import nibabel

    _require_regular(path, role)
    try:
        return nibabel.load(path)
    except FileNotFoundError:
        raise ReportError(f"{path}: the {role} file does not exist") from None
    except Exception as error:  # NiBabel raises many kinds for files it cannot read
        raise ReportError(f"{path}: cannot read the {role} image (NIfTI expected): {error}") from None


def _on_grid(image, path, role, affine, shape):
    # The header's grid first: a small .nii.gz can declare a grid of
    # billions of voxels, which are not read to be refused.
    declared = tuple(int(n) for n in image.shape)
    while len(declared) > 3 and declared[-1] == 1:
        declared = declared[:-1]
    if declared[:3] != tuple(shape) or len(declared) != 3:
        raise ReportError(f"{path}: the {role} image is {'x'.join(map(str, declared))} voxels, the tensors "
                          f"{'x'.join(map(str, shape))}")
    if not np.allclose(image.affine, affine, atol=1e-3 * float(np.abs(affine[:3, :3]).max())):
        raise ReportError(f"{path}: the {role} image is not on the grid of the tensors (another affine)")
    data = np.asanyarray(image.dataobj)
    while data.ndim > 3 and data.shape[-1] == 1:
        data = data[..., 0]
    return data


def read_streamlines(path):
    """Streamlines in RAS millimetres from a .trk or .tck file (NiBabel), or
    from the ASCII legacy VTK polydata that ``stvd path`` writes."""
    if str(path).lower().endswith(".vtk"):
        return _read_vtk_lines(path)
    import nibabel

    _require_regular(path, "paths")
    try:
        return [np.asarray(line, dtype=np.float64) for line in nibabel.streamlines.load(str(path)).streamlines]
    except FileNotFoundError:
        raise ReportError(f"{path}: the paths file does not exist") from None
    except Exception as error:
        raise ReportError(f"{path}: cannot read the paths: {error}") from None


def _read_vtk_lines(path):
    try:
        words = read_regular_text(path, TABLE_BYTES, encoding="ascii").split()
    except OSError as error:
        if error.errno == errno.ENOENT:
            raise ReportError(f"{path}: the paths file does not exist") from None
        raise ReportError(f"{path}: cannot read the paths: {getattr(error, 'reason', None) or error}") from None
    except UnicodeDecodeError as error:
        raise ReportError(f"{path}: cannot read the paths: {error}") from None
    try:
        at = words.index("POINTS")
        count = int(words[at + 1])
        points = np.array(words[at + 3:at + 3 + 3 * count], dtype=np.float64).reshape(count, 3)
        at = words.index("LINES")
        lines, cursor = [], at + 3
        for _ in range(int(words[at + 1])):
            size = int(words[cursor])
            lines.append(points[np.array(words[cursor + 1:cursor + 1 + size], dtype=np.int64)])
            cursor += size + 1
        return lines
    except (ValueError, IndexError):
        raise ReportError(f"{path}: not the ASCII VTK polydata of stvd path") from None


def _read_tsv(path, role):
    try:
        text = read_regular_text(path, TABLE_BYTES)
        return list(csv.DictReader(io.StringIO(text, newline=""), delimiter="\t"))
    except OSError as error:
        if error.errno == errno.ENOENT:
            raise ReportError(f"{path}: the {role} does not exist") from None
        raise ReportError(f"{path}: cannot read the {role}: {getattr(error, 'reason', None) or error}") from None
    except (UnicodeDecodeError, csv.Error) as error:
        raise ReportError(f"{path}: cannot read the {role}: {error}") from None


def _table_number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def _path_rows(rows):
    return [{"path": row.get("path", str(n + 1)), "target": row.get("target", ""),
             "geodesic_mm": _table_number(row.get("geodesic_mm")), "euclidean_mm": _table_number(row.get("euclidean_mm")),
             "mean_fa": _table_number(row.get("mean_fa")), "fallbacks": row.get("fallbacks", "")}
            for n, row in enumerate(rows)]


def connectivity_from_table(path):
    """The matrices of a ``stvd connectivity`` table: labels in the table's
    order, and geodesic_mm and connectivity with NaN on the diagonal and for
    pairs that are not connected."""
    rows = _read_tsv(path, "connectivity table")
    if rows and not {"region_a", "region_b", "geodesic_mm", "connectivity"} <= set(rows[0]):
        raise ReportError(f"{path}: not a stvd connectivity table (columns region_a, region_b, geodesic_mm, "
                          "connectivity)")
    labels = []
    for row in rows:
        for key in ("region_a", "region_b"):
            if row[key] not in labels:
                labels.append(row[key])
    where = {label: n for n, label in enumerate(labels)}
    geodesic = np.full((len(labels), len(labels)), np.nan)
    index = np.full_like(geodesic, np.nan)
    for row in rows:
        a, b = where[row["region_a"]], where[row["region_b"]]
        geodesic[a, b] = _table_number(row["geodesic_mm"])
        index[a, b] = _table_number(row["connectivity"])
    return {"labels": [int(label) if label.lstrip("-").isdigit() else label for label in labels],
            "geodesic_mm": geodesic, "connectivity": index}


def _fa_of_tensors(tensors, parameters, mask):
    """FA computed from the tensors as the tool read them, and the grid."""
    options = {"tensor_order": parameters.get("tensor_order") or None,
               "tensor_frame": parameters.get("tensor_frame") or None,
               "tensor_kind": parameters.get("tensor_kind") or None}
    try:
        field = tensor_field(tensors, None, mask, options)
    except (ValueError, TypeError, OSError) as error:
        raise ReportError(str(error)) from None
    return field


GFA_SOURCE = "the generalised fractional anisotropy of the FOD, from its coefficients (0 outside the domain)"


def _fod_grid(fod, parameters, distance, labels, mask):
    """The grid of an FOD run's page and its background: the distance map's
    grid (distance and path runs) or the labels' (connectivity), and the
    FOD's GFA (docs/fod.md: an FOD has no FA), read from the run's FOD file
    in the basis the run was given, 0 outside the mask."""
    source, role = (distance, "distance map") if distance is not None else (labels, "label")
    if source is None:
        raise ReportError("the page of an FOD run draws its distance map or its labels: give --distance or --labels")
    image = _load_nifti(source, role)
    shape = tuple(int(n) for n in image.shape[:3])
    _require_regular(fod, "FOD input")
    from . import _core

    try:
        gfa, fod_affine = _core.fod_gfa(str(fod), parameters.get("fod_basis_given") or parameters.get("fod_basis"))
    except (ValueError, RuntimeError, OSError) as error:
        raise ReportError(f"{fod}: cannot read the FOD for its GFA: {error}") from None
    if tuple(gfa.shape) != shape or not np.allclose(fod_affine, image.affine,
                                                   atol=1e-3 * float(np.abs(image.affine[:3, :3]).max())):
        raise ReportError(f"{source}: the {role} image is not on the grid of the FOD {fod}")
    background = np.array(gfa, dtype=np.float64)
    if mask is not None:
        background[_on_grid(_load_nifti(mask, "mask"), mask, "mask", image.affine, shape) == 0] = 0.0
    return image.affine, shape, background, GFA_SOURCE


def _content_from_files(statistics_path, distance, paths, paths_table, table, labels, fa):
    try:
        statistics = json.loads(read_regular_text(statistics_path, RECORD_BYTES))
    except OSError as error:
        if error.errno == errno.ENOENT:
            raise ReportError(f"{statistics_path}: the statistics file does not exist") from None
        raise ReportError(f"{statistics_path}: cannot read the statistics (JSON of --stats): "
                          f"{getattr(error, 'reason', None) or error}") from None
    except (UnicodeDecodeError, ValueError, RecursionError) as error:
        raise ReportError(f"{statistics_path}: cannot read the statistics (JSON of --stats): {error}") from None
    if not isinstance(statistics, dict) or "input" not in statistics:
        raise ReportError(f"{statistics_path}: not the --stats file of a stvd run (no \"input\")")
    folder = os.path.dirname(os.path.abspath(statistics_path))
    parameters = statistics.get("parameters", {})
    outputs = statistics.get("outputs", {})
    kind = statistics.get("command", "distance")
    tensors = _resolve(statistics["input"], folder)
    mask = _resolve(parameters.get("mask"), folder)
    if distance is None and kind == "distance":
        distance = _resolve(statistics.get("output"), folder)
    if kind == "connectivity":
        labels = labels or _resolve(parameters.get("labels"), folder)
    if parameters.get("metric") == "fod":
        # An FOD image has no tensors and no FA: the grid is the run's
        # distance map's (or its labels'), on the FOD's grid by construction.
        affine, shape, background, fa_source = _fod_grid(tensors, parameters, distance, labels, mask)
    else:
        field = _fa_of_tensors(tensors, parameters, mask)
        affine, shape = field.affine, field.shape
        background = None
        fa_source = "computed from the tensors (0 outside the domain)"
    if fa is not None:
        fa_data = _on_grid(_load_nifti(fa, "FA"), fa, "FA", affine, shape).astype(np.float64)
        fa_source = f"the image {fa}"
    else:
        fa_data = background if background is not None else np.array(field.fractional_anisotropy, dtype=np.float64)
    content = _RunContent(kind, statistics, affine, shape, fa_data, fa_source)
    if parameters.get("metric") == "fod" and fa is None:
        content.fa_name = "GFA"

    if distance is not None:
        values = _on_grid(_load_nifti(distance, "distance map"), distance, "distance map", affine, shape)
        values = values.astype(np.float64)
        unreachable = parameters.get("unreachable_value")
        values[~np.isfinite(values) | (values < 0)] = np.nan
        if unreachable is not None and np.isfinite(unreachable):
            values[values == unreachable] = np.nan
        content.distance = values
    content.seeds = np.array([seed["voxel"] for seed in statistics.get("seeds", [])], dtype=np.int64).reshape(-1, 3)
    seed_labels = _resolve(parameters.get("seed_labels"), folder)
    if seed_labels:
        content.seed_region = _on_grid(_load_nifti(seed_labels, "seed label"), seed_labels, "seed label", affine,
                                       shape) != 0
        content.seeds = np.zeros((0, 3), np.int64)  # the region is drawn instead of the first 100 voxels
    target_labels = _resolve(parameters.get("target_labels"), folder)
    if target_labels:
        content.target_region = _on_grid(_load_nifti(target_labels, "target label"), target_labels, "target label",
                                         affine, shape) != 0

    if kind == "path" and paths is None:
        paths = _resolve(outputs.get("paths"), folder)
        paths_table = paths_table or _resolve(outputs.get("paths_table"), folder)
    if paths is not None:
        content.paths = read_streamlines(paths)
        if paths_table is not None:
            content.path_rows = _path_rows(_read_tsv(paths_table, "paths table"))
        else:
            content.path_rows = _path_rows([{} for _ in content.paths])
    if kind == "connectivity" and table is None:
        table = _resolve(statistics.get("output"), folder)
    if table is not None:
        content.connectivity = connectivity_from_table(table)
    if labels is not None:
        content.regions = _on_grid(_load_nifti(labels, "label"), labels, "label", affine, shape).astype(np.int64)
    inputs = {"FOD input" if parameters.get("metric") == "fod" else "tensor input": tensors,
              "statistics file": statistics_path, "distance map": distance, "paths": paths,
              "paths table": paths_table, "connectivity table": table, "label image": labels, "FA image": fa,
              "mask": mask, "seed labels": seed_labels, "target labels": target_labels}
    return content, inputs


def write_run_report(output, statistics, *, distance=None, paths=None, paths_table=None, table=None, labels=None,
                     fa=None, subject=None, convention="neurological"):
    """The report page of a run of the ``stvd`` tool, from its files.

    statistics: the run's ``--stats`` JSON; it names the tensors (``input``)
        and, by default, the other files: the distance map of a ``distance``
        run (its ``output``), the paths and their table of a ``path`` run,
        the table and labels of a ``connectivity`` run. Paths in it are taken
        as given, or else relative to the JSON's folder.
    distance: a distance map (NIfTI) on the tensors' grid, e.g. for a path run.
    paths, paths_table: streamlines (.trk, .tck, .vtk) and their TSV.
    table, labels: a connectivity table and its label image.
    fa: an FA image on the tensors' grid; computed from the tensors otherwise.
    subject: the name on the page (default: the tensor file's name).
    convention: 'neurological' (default) or 'radiological'.

    Writes ``output`` atomically (never over an input) and returns the
    page's summary (what the cohort index shows).
    """
    _check_convention(convention)
    _check_extension(output)
    content, inputs = _content_from_files(statistics, distance, paths, paths_table, table, labels, fa)
    outputs = _report_output(output, inputs)
    subject = subject or _subject_of(content.statistics.get("input"))
    text, summary = _render(content, subject, convention)
    _write(outputs, output, text)
    return summary


# ---------------------------------------------------------------------------
# From Python objects


def _tensor_parameters(info):
    """How the tensors of a run from Python were given and read, as its
    field recorded it (``tensor_info``): the page states what the run had."""
    return {"tensor_input": info["input_kind"], "tensor_layout": info["layout"], "tensor_order": info["order"],
            "tensor_order_stated": info["order_was_stated"], "tensor_frame": info["frame"],
            "tensor_frame_stated": info["frame_was_stated"], "tensor_kind": info["tensor_kind"],
            "diffusion_metric": info["diffusion_metric"], "metric_formula": info["metric_formula"],
            "max_anisotropy": info["max_anisotropy"], "fa_threshold": info["fa_threshold"], "mask": info["mask"]}


def _statistics_of_propagation(result, kind, command_line, name):
    counts = dict(result.voxel_counts)
    info = result.tensor_info
    distances = np.asarray(result.distance)
    finite = distances[np.isfinite(distances)]
    statistics = {
        "command": kind, "stvd_version": __version__, "command_line": command_line, "input": name,
        "parameters": {"method": result.method, "k": result.k, "chain_measure": result.chain_measure,
                       "stencil": result.stencil, "domain_connectivity": int(result.domain_connectivity),
                       **_tensor_parameters(info)},
        "seeds": [{"voxel": [int(c) for c in seed]} for seed in np.asarray(result.seeds)[:100]],
        "seed_count": int(len(result.seeds)),
        "label_seeds_left_out": int(result.label_seeds_left_out),
        "voxels": counts,
        "propagation": {"vertices": int(np.prod(result.shape)), "domain_vertices": counts["domain"],
                        "finalized_vertices": int(result.finalized_vertices), "relaxed_edges": int(result.relaxed_edges),
                        "termination": result.termination, "peak_state_bytes": int(result.peak_state_bytes)},
    }
    if finite.size:
        statistics["distance_mm"] = {"reached": int(finite.size), "min": float(finite.min()),
                                     "median": float(np.median(finite)), "max": float(finite.max())}
    return statistics


def _input_name(tensors):
    if is_path(tensors):
        return os.fspath(tensors)
    if is_image(tensors) and tensors.get_filename():
        return tensors.get_filename()
    return "an array"


def _add_paths_and_regions(content, statistics, affine, shape, paths, fallbacks, target_labels, connectivity,
                           labels):
    """What a page draws of a run's paths, target region and connectivity
    (tensor and FOD runs alike); `fallbacks`: one text per path, or None
    (an FOD run's paths have none: "none")."""
    if paths is not None:
        content.paths = [np.asarray(points, np.float64) for points in paths]
        content.path_rows = [{"path": str(n + 1), "target": paths.targets[n],
                              "geodesic_mm": float(paths.geodesic_mm[n]), "euclidean_mm": float(paths.euclidean_mm[n]),
                              "mean_fa": float(paths.mean_fa[n]), "fallbacks": fallbacks[n] if fallbacks else "none"}
                             for n in range(len(paths))]
    if target_labels is not None:
        content.target_region = _array_on_grid(target_labels, "target_labels", affine, shape) != 0
    if connectivity is not None:
        content.connectivity = {"labels": [int(v) for v in connectivity.labels],
                                "geodesic_mm": np.asarray(connectivity.geodesic_mm),
                                "connectivity": np.asarray(connectivity.connectivity)}
        statistics["regions"] = {"count": len(connectivity.labels),
                                 "left_out": int(getattr(connectivity, "labels_left_out", 0))}
        if labels is not None:
            content.regions = _array_on_grid(labels, "labels", affine, shape).astype(np.int64)


def write_report(output, result=None, *, paths=None, connectivity=None, labels=None, tensors=None, affine=None,
                 mask=None, tensor_order=None, tensor_frame=None, tensor_kind=None, diffusion_metric=None,
                 max_anisotropy=None, fa_threshold=None, accept_implausible_tensors=False,
                 accept_misaligned_tensors=False, fa=None, subject=None, convention="neurological", command_line=None,
                 target_labels=None):
    """The report page of a run made from Python.

    result: the ``stvd.Propagation`` of ``stvd.propagate`` (the distance map,
        seeds, statistics and grid); ``tensors`` is enough for a
        connectivity-only page: what ``stvd.distance`` takes, with the same
        keywords (``affine=`` for an array, ``tensor_order``, ``mask``, ...);
        without them the tensors are read as the connectivity run read them.
        With ``result`` the tensors and their options are the result's.
    paths: the ``stvd.Paths`` of ``stvd.trace_paths``; ``target_labels``: the
        label image its ``target_labels=`` were (path, NiBabel image or array
        on the grid), outlined on the slices.
    connectivity, labels: the ``stvd.Connectivity`` of ``stvd.connectivity``
        and its label image (path, NiBabel image or array on the grid).
    fa: an FA array or image on the grid; computed from the tensors otherwise.
    subject, convention: as for ``write_run_report``; command_line: what the
        page records as the command (default: this process's ``sys.argv``).

    FOD runs (docs/fod.md): ``result`` the image ``stvd.fod_distance``
    returned, ``paths`` the ``stvd.Paths`` of ``stvd.fod_paths``,
    ``connectivity`` the ``stvd.Connectivity`` of ``stvd.fod_connectivity``
    (with ``labels``); the page is the one the tool's ``--report`` writes
    for the same run, over the FOD's GFA (0 outside ``mask``, by default
    the run's own mask); the tensor keywords are refused.

    Writes ``output`` atomically and returns the page's summary.
    """
    from . import Propagation

    _check_convention(convention)
    fod_run = _fod_run_of(result, paths, connectivity)
    if fod_run is not None:
        if tensors is not None or affine is not None or accept_implausible_tensors or accept_misaligned_tensors or any(
                v is not None for v in (tensor_order, tensor_frame, tensor_kind, diffusion_metric, max_anisotropy,
                                        fa_threshold)):
            raise ValueError("write_report: an FOD run's page takes its grid and metric from the run's objects; "
                             "tensor keywords do not apply")
        return _write_fod_report(output, result, paths, connectivity, labels, target_labels, mask, fa, subject,
                                 convention, command_line)
    if result is None and tensors is None:
        raise TypeError("write_report: give the stvd.Propagation (result=) or, for connectivity alone, tensors=")
    if result is not None and not isinstance(result, Propagation):
        raise TypeError("result: expected the stvd.Propagation that stvd.propagate returns")
    if command_line is None:
        command_line = "python3 " + " ".join(sys.argv)
    kind = "connectivity" if connectivity is not None and paths is None else ("path" if paths is not None else "distance")
    outputs = _report_output(output, {"tensor input": tensors, "mask": mask, "label image": labels, "FA image": fa,
                                      "target labels": target_labels})

    tensor_options = dict(tensor_order=tensor_order, tensor_frame=tensor_frame, tensor_kind=tensor_kind,
                          diffusion_metric=diffusion_metric, max_anisotropy=max_anisotropy, fa_threshold=fa_threshold)
    if result is not None:
        if mask is not None or accept_implausible_tensors or accept_misaligned_tensors or any(
                v is not None for v in tensor_options.values()):
            raise ValueError("write_report: the tensor options come from the stvd.Propagation given (result=)")
        field = result._result.field
        if affine is not None and not np.allclose(np.asarray(affine, np.float64), field.affine, atol=1e-4):
            raise ValueError("affine: not the affine of the stvd.Propagation given (result=)")
        info = field.tensor_info
        statistics = _statistics_of_propagation(result, kind, command_line, info["input"])
    else:
        # The grid and FA from the tensors, read as the connectivity run read
        # them; what the page states about the run is that run's record.
        # Options given here are taken as given (an array's affine= too).
        info = getattr(connectivity, "tensor_info", None)
        options = dict(tensor_options, accept_implausible_tensors=bool(accept_implausible_tensors),
                       accept_misaligned_tensors=bool(accept_misaligned_tensors))
        if info is not None and all(v is None for v in tensor_options.values()):
            options.update({"accept_implausible_tensors": True, "accept_misaligned_tensors": True,
                            "tensor_order": info["order"] if info["order_was_stated"] else None,
                            "tensor_frame": info["frame"] if info["frame_was_stated"] else None,
                            "tensor_kind": info["tensor_kind"]})
        field = tensor_field(tensors, affine, mask, options)
        info = info or field.tensor_info
        statistics = {"command": kind, "stvd_version": __version__, "command_line": command_line,
                      "input": info["input"], "parameters": _tensor_parameters(info),
                      "voxels": dict(getattr(connectivity, "voxel_counts", None) or field.voxel_counts)}
    affine, shape = field.affine, field.shape
    if fa is not None:
        fa_data, fa_source = _array_on_grid(fa, "fa", affine, shape).astype(np.float64), "given"
    else:
        fa_data, fa_source = np.array(field.fractional_anisotropy, np.float64), "computed from the tensors (0 outside the domain)"
    content = _RunContent(kind, statistics, affine, shape, fa_data, fa_source)
    if result is not None:
        content.distance = np.where(np.isfinite(result.distance), result.distance, np.nan)
        content.seeds = np.asarray(result.seeds, dtype=np.int64).reshape(-1, 3)
        if len(content.seeds) > 100:  # label seeds: the region is drawn instead
            content.seed_region = np.zeros(shape, bool)
            content.seed_region[tuple(content.seeds.T)] = True
            content.seeds = np.zeros((0, 3), np.int64)
    fallbacks = [",".join(f"{k}={v}" for k, v in f.items() if v) or "none"
                 for f in paths.fallbacks] if paths is not None else None
    _add_paths_and_regions(content, statistics, affine, shape, paths, fallbacks, target_labels, connectivity, labels)
    # Named after the tensors' file; a run on an array is just "run".
    subject = subject or _subject_of(field.name if field.tensor_info["input_kind"] == "file" or
                                     field.name != "tensors" else None)
    text, summary = _render(content, subject, convention)
    _write(outputs, output, text)
    return summary


def _fod_run_of(result, paths, connectivity):
    """The record of an FOD run (stvd._fod.FodRun) that one of the objects
    holds: the image of stvd.fod_distance, the stvd.Paths of stvd.fod_paths,
    the stvd.Connectivity of stvd.fod_connectivity; None for tensor runs."""
    extra = getattr(result, "extra", None)
    if isinstance(extra, dict) and extra.get("stvd_fod_run") is not None:
        return extra["stvd_fod_run"]
    for value in (paths, connectivity):
        if getattr(value, "fod_run", None) is not None:
            return value.fod_run
    if result is not None and is_image(result):
        raise TypeError("result: a NiBabel image that stvd.fod_distance did not return (it holds no FOD run); "
                        "for a map on disk use write_run_report with the run's --stats")
    return None


def _write_fod_report(output, result, paths, connectivity, labels, target_labels, mask, fa, subject, convention,
                      command_line):
    """The page of an FOD run from the objects of stvd.fod_distance
    (``result``: its image), stvd.fod_paths and stvd.fod_connectivity: what
    the tool's ``--report`` draws for the same run (docs/fod.md, "The
    tool")."""
    extra = getattr(result, "extra", None)
    distance_run = extra.get("stvd_fod_run") if isinstance(extra, dict) else None
    paths_run = getattr(paths, "fod_run", None) if paths is not None else None
    connectivity_run = getattr(connectivity, "fod_run", None) if connectivity is not None else None
    for value, run, what in ((result, distance_run, "result: the image of stvd.fod_distance"),
                             (paths, paths_run, "paths: the stvd.Paths of stvd.fod_paths"),
                             (connectivity, connectivity_run, "connectivity: the stvd.Connectivity of "
                                                             "stvd.fod_connectivity")):
        if value is not None and run is None:
            raise TypeError(f"{what} (a tensor run's does not go on an FOD run's page)")
    run = paths_run or distance_run or connectivity_run
    kind = "connectivity" if connectivity is not None and paths is None else ("path" if paths is not None else "distance")
    if command_line is None:
        command_line = "python3 " + " ".join(sys.argv)
    outputs = _report_output(output, {"FOD input": run.input_file, "mask": mask, "label image": labels,
                                      "FA image": fa, "target labels": target_labels})
    statistics = json.loads(json.dumps(run.statistics))  # a copy
    statistics.update({"command": kind, "command_line": command_line})
    affine, shape = run.affine, run.shape
    for other in (distance_run, paths_run, connectivity_run):
        if other is not None and (other.shape != shape or not np.allclose(other.affine, affine, atol=1e-4)):
            raise ValueError("write_report: the runs given are on different grids")
    background, background_source, name = _fod_background(run, mask, affine, shape), GFA_SOURCE, "GFA"
    if fa is not None:
        background, background_source, name = _array_on_grid(fa, "fa", affine, shape).astype(np.float64), "given", "FA"
    content = _RunContent(kind, statistics, affine, shape, background, background_source)
    content.fa_name = name
    if result is not None:
        values = np.asanyarray(result.dataobj).astype(np.float64)
        unreachable = distance_run.statistics["parameters"].get("unreachable_value")
        values[~np.isfinite(values) | (values < 0)] = np.nan
        if unreachable is not None and np.isfinite(unreachable):
            values[values == unreachable] = np.nan
        content.distance = values
    elif paths_run is not None and paths_run.distance is not None:
        content.distance = paths_run.distance
    seeds = run.seeds
    if len(seeds) > 100:  # label seeds: the region is drawn instead
        content.seed_region = np.zeros(shape, bool)
        content.seed_region[tuple(seeds.T)] = True
        seeds = np.zeros((0, 3), np.int64)
    content.seeds = seeds
    _add_paths_and_regions(content, statistics, affine, shape, paths, None, target_labels, connectivity, labels)
    subject = subject or _subject_of(run.input_file)  # named after the FOD's file; a run on an array is "run"
    text, summary = _render(content, subject, convention)
    _write(outputs, output, text)
    return summary


def _fod_background(run, mask, affine, shape):
    """The background of an FOD run's page from Python, as the tool's page
    of the run draws it (_fod_grid): the FOD's GFA, 0 outside the mask."""
    background = np.array(run.gfa, dtype=np.float64)
    mask = mask if mask is not None else run.mask
    if mask is not None:
        background[_array_on_grid(mask, "mask", affine, shape) == 0] = 0.0
    return background


def _array_on_grid(value, name, affine, shape):
    if is_path(value):
        return _on_grid(_load_nifti(value, name), value, name, affine, shape)
    if is_image(value):
        return _on_grid(value, _input_name(value), name, affine, shape)
    array = np.asarray(value)
    if array.shape[:3] != tuple(shape):
        raise ValueError(f"{name}: an array of shape {array.shape} on a grid of {shape}")
    return array


# ---------------------------------------------------------------------------
# The cohort index


def status_tally(counts):
    """'2 ok, 1 with a warning, 3 with warnings, 1 failed' from {status: count}."""
    def words(status, n):
        if status == "warnings":
            return f"{n} with {'a warning' if n == 1 else 'warnings'}"
        return f"{n} {status}"
    return ", ".join(words(status, n) for status, n in sorted(counts.items()))


def _summary_of_page(path):
    """The run summary of the page at ``path``, or None: read only when it is
    a regular file of at most ``PAGE_BYTES`` (a FIFO or a link to /dev/zero
    named like a page is never read), kept only in the fields and types a
    summary has (it may come from a page anyone could have put there)."""
    try:
        summary = page.read_summary(read_regular_text(path, PAGE_BYTES))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError):
        return None
    if summary is None:
        return None
    clean = {}
    for key in ("subject", "kind", "status", "input", "stvd_version", "thumbnail", "error"):
        value = summary.get(key)
        if isinstance(value, (str, int, float)) and not isinstance(value, bool):
            clean[key] = str(value)
    if "subject" not in clean:
        return None
    warnings = summary.get("warnings")
    clean["warnings"] = warnings if isinstance(warnings, int) and not isinstance(warnings, bool) else 0
    figures = summary.get("figures")
    if isinstance(figures, dict):
        clean["figures"] = {str(k): v for k, v in figures.items()
                            if isinstance(v, (str, int, float)) and not isinstance(v, bool)}
    return clean


def cohort_entries_from_folder(folder):
    """The cohort index's entries for a folder of reports: every ``.html``
    page with a run summary in the folder and its subfolders (one level, as
    a cohort's ``OUTDIR/<subject>/`` holds them), in name order. A subfolder
    without a report is listed as ``missing``. Pages are read only when they
    are regular files of at most ``PAGE_BYTES``."""
    entries = []
    try:
        names = sorted(os.listdir(folder))
    except OSError as error:
        raise ReportError(f"{folder}: cannot list the folder: {error.strerror}") from None
    for name in names:
        path = os.path.join(folder, name)
        pages = []
        if os.path.isdir(path):
            try:
                pages = [os.path.join(path, n) for n in sorted(os.listdir(path)) if n.endswith(".html")]
            except OSError:  # a folder that cannot be listed holds no page we can show
                pages = []
        elif name.endswith(".html"):
            pages = [path]
        found = False
        for candidate in pages:
            summary = _summary_of_page(candidate)
            if summary is not None:
                entries.append(dict(summary, report=candidate))
                found = True
        if os.path.isdir(path) and not found:
            entries.append({"subject": name, "status": "missing", "error": "no report in the folder"})
    return entries


def write_cohort_index(output, subjects, *, title="stvd cohort"):
    """The cohort index page: one row per subject with its status, key
    figures and thumbnail, linking to its page.

    subjects: a list of dicts, each with ``subject`` and ``status`` (``ok``,
    ``warnings``, ``failed`` or ``missing``) and optionally ``report`` (the
    path of its page, linked relative to the index), ``error`` (the one-line
    error of a failed subject), ``figures`` (a dict of key figures),
    ``thumbnail`` (a data URI) and ``warnings`` (a count). The summaries that
    ``write_run_report`` and ``write_report`` return, with ``report=`` added,
    are such dicts. Writes ``output`` atomically; returns the counts per
    status.
    """
    entries = list(subjects)
    outputs = _report_output(output, [(f"report of {e.get('subject')}", e.get("report")) for e in entries])
    folder = os.path.dirname(os.path.abspath(output))
    figure_keys = []
    for entry in entries:
        for key in (entry.get("figures") if isinstance(entry.get("figures"), dict) else {}):
            if key not in figure_keys:
                figure_keys.append(key)
    rows = []
    counts = {}
    for entry in entries:
        status = entry.get("status") if entry.get("status") in page.STATUSES else "missing"
        counts[status] = counts.get(status, 0) + 1
        report = entry.get("report")
        # Only pages inside the index's folder are linked, by a relative
        # path (page.safe_link); only data: PNG thumbnails are shown.
        href = page.safe_link(os.path.relpath(os.path.abspath(report), folder)) if report else None
        subject = page.escape(entry.get("subject", "?"))
        name = f"<a href=\"{page.escape(href)}\">{subject}</a>" if href else subject
        picture = ""
        thumbnail = page.safe_image(entry.get("thumbnail"))
        if thumbnail:
            picture = f"<img src=\"{thumbnail}\" alt=\"axial slice of {subject}\">"
            if href:
                picture = f"<a href=\"{page.escape(href)}\">{picture}</a>"
        detail = str(entry.get("error") or "")  # escaped by page.table
        if report and not href:
            detail = "its page lies outside the index's folder and is not linked" + (f"; {detail}" if detail else "")
        warnings = entry.get("warnings")
        if isinstance(warnings, int) and not isinstance(warnings, bool) and warnings:
            detail = f"{warnings} warning{'' if warnings == 1 else 's'}" + (f"; {detail}" if detail else "")
        figures = entry.get("figures") if isinstance(entry.get("figures"), dict) else {}
        rows.append([name, page.status_badge(status), picture, detail] +
                    [figures.get(key, "") for key in figure_keys])
    header = ["subject", "status", "axial slice", "warnings or error"] + [_FIGURE_LABELS.get(k, k) for k in figure_keys]
    body = (f"<h1>{page.escape(title)}</h1><p id=\"stvd-cohort-counts\">{len(entries)} "
            f"subject{'' if len(entries) == 1 else 's'}: {page.escape(status_tally(counts))}."
            f" Made by stvd {page.escape(__version__)} on {datetime.datetime.now().strftime('%Y-%m-%d %H:%M')}.</p>"
            + "<div class=\"cohort\">" + page.table(header, rows, "stvd-cohort", raw_columns=(0, 1, 2)) + "</div>")
    _write(outputs, output, page.page(title, body))
    return counts


def cohort_index_from_folder(folder, output=None, *, title=None):
    """The cohort index of a folder of reports (``cohort_entries_from_folder``),
    written to ``output`` (default: ``FOLDER/index.html``). Returns the
    counts per status."""
    output = output or os.path.join(folder, "index.html")
    # An index made before has no run summary and is no entry; a subject's
    # page is one, and an output that is one of them is refused (the pages
    # an index reads are its inputs).
    entries = cohort_entries_from_folder(folder)
    return write_cohort_index(output, entries, title=title or f"stvd cohort: {os.path.basename(os.path.abspath(folder))}")


# ---------------------------------------------------------------------------
# Shared steps


def _subject_of(path):
    name = os.path.basename(str(path or "run"))
    for extension in (".nii.gz", ".nii", ".nrrd", ".nhdr", ".mif.gz", ".mif", ".mih"):
        if name.endswith(extension):
            return name[:-len(extension)]
    return name


def _check_convention(convention):
    if convention not in CONVENTIONS:
        raise ValueError(f"convention: expected one of {', '.join(CONVENTIONS)}, got {convention!r}")


def _check_extension(output):
    if not str(output).endswith((".html", ".htm")):
        raise ReportError(f"{output}: a report is an .html file", EXIT_USAGE)


def _report_output(output, inputs):
    """The page as the package writes every output (``stvd.OutputFiles``):
    compared with every input by identity before anything is drawn; a
    conflict is a usage error, as in the tool. ``inputs``: role and path (or
    NiBabel image, or None) pairs, or a dict of them."""
    _check_extension(output)
    try:
        return OutputFiles({"QC report": output}, inputs=inputs)
    except FileConflictError as error:
        raise ReportError(str(error), EXIT_USAGE) from None
    except OutputError as error:
        raise ReportError(str(error), EXIT_OUTPUT) from None


def _write(outputs, output, text):
    """Writes the page through ``outputs`` (staged, flushed, renamed)."""
    def write(staging):
        with open(staging, "w", encoding="utf-8") as file:
            file.write(text)

    try:
        with outputs:
            outputs.write(output, write)
    except OutputError as error:
        raise ReportError(str(error), EXIT_OUTPUT) from None



# ---------------------------------------------------------------------------
# The command line (``stvd report`` runs it)


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        raise ReportError(f"report: {message} (see stvd report --help)", EXIT_USAGE)


def _parser():
    parser = _Parser(prog="stvd report", description=(
        "A self-contained HTML page for a stvd run (from its --stats JSON and outputs), or the cohort index of a "
        "folder of reports. See docs/report.md."))
    parser.add_argument("--stats", metavar="RUN.json", help="the run's --stats file (names the tensors and outputs)")
    parser.add_argument("--distance", metavar="MAP", help="a distance map (NIfTI) on the tensors' grid")
    parser.add_argument("--paths", metavar="PATHS", help="streamlines of stvd path (.trk, .tck, .vtk)")
    parser.add_argument("--paths-table", metavar="TSV", help="their TSV summary")
    parser.add_argument("--table", metavar="TSV", help="a stvd connectivity table")
    parser.add_argument("--labels", metavar="LABELS", help="the connectivity run's label image")
    parser.add_argument("--fa", metavar="FA", help="an FA image on the tensors' grid (default: computed)")
    parser.add_argument("--subject", help="the name on the page (default: the tensor file's name)")
    parser.add_argument("--convention", choices=list(CONVENTIONS), default="neurological",
                        help="how slices are shown (default neurological)")
    parser.add_argument("--index", metavar="FOLDER", help="make the cohort index of a folder of reports instead")
    # stvd --report starts this while the run computes (see _prepare).
    parser.add_argument("--prepare", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("-o", "--output", metavar="REPORT.html", help="the page to write")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing on success")
    return parser


def _check_dependencies():
    """The packages drawing needs; one line naming what is missing."""
    missing = []
    for module, package in (("matplotlib", "python3-matplotlib"), ("nibabel", "python3-nibabel")):
        try:
            __import__(module)
        except ImportError:
            missing.append(f"{module} (Debian: {package})")
    if missing:
        raise ReportError("report: the report needs " + " and ".join(missing) + " for " + sys.executable,
                          EXIT_INTERNAL)
    import matplotlib

    matplotlib.use("Agg")


def _prepare():
    """For ``stvd ... --report``, started while the run computes: checks that
    drawing works and does what every page costs first (the imports, one
    small picture), says ``ready`` on stderr, then reads the page's
    arguments, separated by NUL bytes, from stdin. None: the run stopped, and
    there is nothing to draw."""
    from ._report_slices import new_figure, png_bytes

    figure, axes = new_figure(10, 10)
    axes.imshow(np.zeros((2, 2)), cmap="gray")
    axes.contour(np.arange(9.0).reshape(3, 3), levels=[4.0])
    png_bytes(figure)
    print("ready", file=sys.stderr, flush=True)
    text = sys.stdin.buffer.read().decode("utf-8", "surrogateescape")
    return [a for a in text.split("\0") if a] if text else None


def main(argv=None):
    """``stvd report``: returns the exit code; failures print one line."""
    start = time.perf_counter()
    try:
        arguments = _parser().parse_args(argv)
        _check_dependencies()
        if arguments.prepare:
            page_arguments = _prepare()
            if page_arguments is None:
                return 0
            start = time.perf_counter()
            arguments = _parser().parse_args(page_arguments)
        if not arguments.output:
            raise ReportError("report: no output: add -o REPORT.html", EXIT_USAGE)
        if arguments.index:
            counts = cohort_index_from_folder(arguments.index, arguments.output)
            message = f"Wrote the cohort index {arguments.output}: " + status_tally(counts)
        else:
            if not arguments.stats:
                raise ReportError("report: no run: add --stats RUN.json (or --index FOLDER)", EXIT_USAGE)
            summary = write_run_report(arguments.output, arguments.stats, distance=arguments.distance,
                                       paths=arguments.paths, paths_table=arguments.paths_table, table=arguments.table,
                                       labels=arguments.labels, fa=arguments.fa, subject=arguments.subject,
                                       convention=arguments.convention)
            count = summary["warnings"]
            message = (f"Wrote the report {arguments.output} ({summary['status']}, {count} "
                       f"warning{'' if count == 1 else 's'}) "
                       f"in {time.perf_counter() - start:.2f} s.")
        if not arguments.quiet:
            print(message)
        return 0
    except ReportError as error:
        print(f"stvd: {error}", file=sys.stderr)
        return error.exit_code
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    from ._interruption import ending_by_signal

    with ending_by_signal():
        sys.exit(main())

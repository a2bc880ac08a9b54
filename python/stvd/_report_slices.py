"""The report's slices: the axial, coronal and sagittal planes through a
point, turned to the image's nearest RAS axes, shown in a stated convention,
with the L/R/A/P/S/I letter of each edge taken from the direction cosines.

Drawing uses matplotlib's Agg canvas directly: no display, no pyplot state,
and matplotlib's own defaults (``matplotlib_defaults``): a ``matplotlibrc`` in
the working folder, which matplotlib reads first, or the user's, changes
nothing on a page and runs nothing (``text.usetex`` would run LaTeX).
"""

import functools
import io

import numpy as np

CONVENTIONS = {
    # The patient's left on the left of the screen (as seen from above and behind).
    "neurological": "the patient's left is on the left of the screen",
    # The patient's left on the right of the screen (as seen from below and in front).
    "radiological": "the patient's left is on the right of the screen",
}

# The seed marker's colour, used nowhere else on a slice (the colour maps are
# viridis and grey, paths and regions take tab10/tab20 colours), so that a
# test finds the marker in the picture.
SEED_COLOUR = "#ff00ff"
# Target regions (path runs with label targets): cyan, likewise in no map.
TARGET_COLOUR = "#00ffff"
# The distance map over FA: opaque enough to read its colour, light enough
# that the FA underneath (the tracts the distances follow) stays visible.
DISTANCE_ALPHA = 0.35

# Each plane: the axis of the turned grid it cuts (R, A, S = 0, 1, 2), the
# axis shown across and the axis shown upwards.
PLANES = {
    "axial": (2, 0, 1),
    "coronal": (1, 0, 2),
    "sagittal": (0, 1, 2),
}

PIXELS_PER_MM = 1.75
MAX_SIDE_PIXELS = 640


def edge_letter(direction):
    """The anatomical letter a world direction (RAS millimetres) points to
    most: R or L, A or P, S or I."""
    axis = int(np.argmax(np.abs(direction)))
    return ("RAS" if direction[axis] > 0 else "LPI")[axis]


class DisplayGrid:
    """A voxel grid turned to the RAS axes nearest to its own (NiBabel's
    io_orientation of the affine): arrays come out with their first axis
    pointing to the right, the second anterior, the third superior."""

    def __init__(self, affine, shape):
        from nibabel import orientations

        self.source_affine = np.asarray(affine, dtype=np.float64)
        self.source_shape = tuple(int(n) for n in shape[:3])
        self.ornt = orientations.io_orientation(self.source_affine)
        to_source = orientations.inv_ornt_aff(self.ornt, self.source_shape)
        self.affine = self.source_affine @ to_source
        self.shape = tuple(int(self.source_shape[int(a)]) for a in np.argsort(self.ornt[:, 0]))
        self.zooms = np.sqrt((self.affine[:3, :3] ** 2).sum(axis=0))
        self._inverse = np.linalg.inv(self.affine)

    def orientation_code(self):
        """The source grid's axis codes (e.g. LAS), from its direction cosines."""
        from nibabel import orientations

        return "".join(orientations.aff2axcodes(self.source_affine))

    def obliquity_degrees(self):
        """The largest angle between a voxel axis and its nearest RAS axis."""
        cosines = self.affine[:3, :3] / self.zooms
        return float(np.degrees(np.arccos(np.clip(np.abs(np.diag(cosines)).min(), -1.0, 1.0))))

    def turn(self, volume):
        """A volume on the source grid as an array on the turned grid."""
        from nibabel import orientations

        return orientations.apply_orientation(np.asanyarray(volume), self.ornt)

    def index_of_points(self, ras):
        """Continuous indices on the turned grid of RAS points, (N, 3)."""
        ras = np.asarray(ras, dtype=np.float64).reshape(-1, 3)
        return ras @ self._inverse[:3, :3].T + self._inverse[:3, 3]

    def index_of_voxels(self, voxels):
        """Indices on the turned grid of voxel indices on the source grid."""
        voxels = np.asarray(voxels, dtype=np.float64).reshape(-1, 3)
        ras = voxels @ self.source_affine[:3, :3].T + self.source_affine[:3, 3]
        return np.rint(self.index_of_points(ras)).astype(np.int64)


class Panel:
    """One plane through a point: which way is across and up on the screen,
    and the letters at its four edges."""

    def __init__(self, grid, plane, through, convention):
        if convention not in CONVENTIONS:
            raise ValueError(f"convention: expected one of {', '.join(CONVENTIONS)}, got {convention!r}")
        self.grid = grid
        self.plane = plane
        self.normal, self.across, self.up = PLANES[plane]
        self.index = int(np.clip(through[self.normal], 0, grid.shape[self.normal] - 1))
        # Across the screen: +R for neurological axial and coronal slices, +L
        # for radiological ones; sagittal slices face the patient's left side
        # with anterior on the left, as radiology shows them in either
        # convention.
        if plane == "sagittal":
            self.across_sign = -1
        else:
            self.across_sign = 1 if convention == "neurological" else -1
        right = self.across_sign * grid.affine[:3, self.across]
        up = grid.affine[:3, self.up]
        self.letters = {"right": edge_letter(right), "left": edge_letter(-right),
                        "top": edge_letter(up), "bottom": edge_letter(-up)}
        # The slice as the source grid numbers it (the heading's voxel): the
        # source axis the plane cuts, and its index there.
        self.source_axis = int(np.nonzero(grid.ornt[:, 0] == self.normal)[0][0])
        flipped = grid.ornt[self.source_axis, 1] < 0
        size = grid.source_shape[self.source_axis]
        self.source_index = size - 1 - self.index if flipped else self.index
        self.extent_mm = (grid.shape[self.across] * grid.zooms[self.across],
                          grid.shape[self.up] * grid.zooms[self.up])

    def image(self, turned):
        """The plane of a turned array as rows (bottom to top) and columns
        (left to right on the screen)."""
        # np.take drops the normal axis; the two left keep their order, which
        # is (across, up) for every plane.
        cut = np.take(turned, self.index, axis=self.normal)
        if self.across_sign < 0:
            cut = cut[::-1, :]
        return cut.T

    def screen_mm(self, indices):
        """Screen positions (x to the right, y upwards, millimetres from the
        lower left corner) of continuous indices on the turned grid."""
        indices = np.asarray(indices, dtype=np.float64).reshape(-1, 3)
        across = indices[:, self.across]
        if self.across_sign < 0:
            across = self.grid.shape[self.across] - 1 - across
        return np.column_stack(((across + 0.5) * self.grid.zooms[self.across],
                                (indices[:, self.up] + 0.5) * self.grid.zooms[self.up]))

    def caption(self):
        """'sagittal slice i = 55': the plane and the source voxel index it
        holds, as the heading's voxel (i, j, k) counts it."""
        return f"{self.plane} slice {'ijk'[self.source_axis]} = {self.source_index}"

    def contains(self, indices):
        """Which of the integer indices lie in this plane."""
        return np.asarray(indices).reshape(-1, 3)[:, self.normal] == self.index


def contour_step(maximum):
    """A round iso-distance spacing that gives about 8 to 12 contours."""
    if not np.isfinite(maximum) or maximum <= 0:
        return None
    raw = maximum / 10.0
    magnitude = 10.0 ** np.floor(np.log10(raw))
    for factor in (1, 2, 2.5, 5, 10):
        if factor * magnitude >= raw:
            return factor * magnitude
    return 10 * magnitude


def matplotlib_defaults(draw):
    """Runs ``draw`` with matplotlib's built-in settings (its "default"
    style), whatever matplotlibrc file matplotlib found."""

    @functools.wraps(draw)
    def drawn(*args, **kwargs):
        import matplotlib.style

        with matplotlib.style.context("default"):
            return draw(*args, **kwargs)

    return drawn


def new_figure(width_mm, height_mm, scale=1.0):
    """A figure of the panel's physical size at PIXELS_PER_MM (capped), with
    one axes filling it."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    pixels_per_mm = min(PIXELS_PER_MM, MAX_SIDE_PIXELS / max(width_mm, height_mm)) * scale
    dpi = 100.0
    figure = Figure(figsize=(width_mm * pixels_per_mm / dpi, height_mm * pixels_per_mm / dpi), dpi=dpi)
    FigureCanvasAgg(figure)
    axes = figure.add_axes((0, 0, 1, 1))
    axes.set_axis_off()
    axes.set_xlim(0, width_mm)
    axes.set_ylim(0, height_mm)
    return figure, axes


def png_bytes(figure):
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=figure.dpi)
    return buffer.getvalue()


@matplotlib_defaults
def draw_panel(panel, layers, scale=1.0):
    """The panel as PNG bytes. ``layers`` holds the turned arrays and
    overlays (see report._SliceLayers): fa, distance (NaN where not
    reached) with its colour range and contour step, regions (labels) with
    colours, seed voxels, a seed region, and paths with their colours."""
    from matplotlib.colors import ListedColormap

    figure, axes = new_figure(*panel.extent_mm, scale=scale)
    extent = (0, panel.extent_mm[0], 0, panel.extent_mm[1])
    show = dict(origin="lower", extent=extent, interpolation="nearest", aspect="auto")
    axes.imshow(panel.image(layers.fa), cmap="gray", vmin=0.0, vmax=1.0, **show)
    if layers.regions is not None:
        regions = panel.image(layers.regions).astype(np.float64)
        regions[regions == 0] = np.nan
        axes.imshow(regions, cmap=ListedColormap(layers.region_colours), vmin=0, vmax=len(layers.region_colours),
                    alpha=0.75, **show)
    if layers.distance is not None:
        distance = panel.image(layers.distance)
        axes.imshow(np.ma.masked_invalid(distance), cmap="viridis", vmin=0.0, vmax=layers.distance_max,
                    alpha=DISTANCE_ALPHA, **show)
        if layers.contour_step and np.isfinite(distance).any():
            ny, nx = distance.shape
            xs = (np.arange(nx) + 0.5) * panel.extent_mm[0] / nx
            ys = (np.arange(ny) + 0.5) * panel.extent_mm[1] / ny
            levels = np.arange(layers.contour_step, layers.distance_max, layers.contour_step)
            if levels.size:
                axes.contour(xs, ys, np.where(np.isfinite(distance), distance, layers.distance_max * 2), levels=levels,
                             colors="white", linewidths=0.6, alpha=0.8)
    # Seed and target regions as outlines over a light tint: what lies inside
    # them (FA, the distance, where the paths start and end) stays visible.
    for region_layer, colour in ((layers.seed_region, SEED_COLOUR), (layers.target_region, TARGET_COLOUR)):
        if region_layer is None:
            continue
        region = panel.image(region_layer).astype(np.float64)
        if not region.any():
            continue
        tint = np.where(region > 0, 1.0, np.nan)
        axes.imshow(tint, cmap=ListedColormap([colour]), vmin=0, vmax=1, alpha=0.3, **show)
        _outline(axes, panel, region, colour)
    # The seed voxels as hollow rings, under the paths that start in them.
    marked = layers.seeds[panel.contains(layers.seeds)] if len(layers.seeds) else layers.seeds
    if len(marked):
        xy = panel.screen_mm(marked)
        axes.plot(xy[:, 0], xy[:, 1], "o", markerfacecolor="none", markeredgecolor=SEED_COLOUR, markersize=13,
                  markeredgewidth=2.0)
    for points, colour in zip(layers.paths, layers.path_colours):
        xy = panel.screen_mm(points)
        axes.plot(xy[:, 0], xy[:, 1], color=colour, linewidth=1.6, solid_capstyle="round")
        axes.plot(xy[-1:, 0], xy[-1:, 1], "o", color=colour, markersize=4)
    return png_bytes(figure)


def _outline(axes, panel, region, colour):
    """The boundary of a voxel region in the slice, along voxel edges."""
    ny, nx = region.shape
    # Upsampled by 4 so that the contour follows the voxel edges, not the
    # diagonals between voxel centres.
    fine = np.kron(region > 0, np.ones((4, 4))).astype(np.float64)
    xs = (np.arange(4 * nx) + 0.5) * panel.extent_mm[0] / (4 * nx)
    ys = (np.arange(4 * ny) + 0.5) * panel.extent_mm[1] / (4 * ny)
    axes.contour(xs, ys, fine, levels=[0.5], colors=colour, linewidths=1.5)

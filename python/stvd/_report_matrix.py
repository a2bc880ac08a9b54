"""The connectivity matrix of a report as a heat map with the region labels."""

import numpy as np

from ._report_slices import matplotlib_defaults, png_bytes


@matplotlib_defaults
def draw_heatmap(matrix, labels, title, colour_map, unit):
    """Row a, column b: the value measured from region a to region b; pairs
    without a value (the diagonal, not connected) are grey. PNG bytes."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    n = len(labels)
    side = min(7.5, 2.8 + 0.16 * n)
    figure = Figure(figsize=(side + 1.2, side), dpi=100)
    FigureCanvasAgg(figure)
    axes = figure.add_axes((0.14, 0.12, 0.68, 0.8))
    shown = np.ma.masked_invalid(np.asarray(matrix, dtype=np.float64))
    cmap = matplotlib.colormaps[colour_map].with_extremes(bad="#d0d0d0")
    image = axes.imshow(shown, cmap=cmap, interpolation="nearest")
    # At most about 40 tick labels, so that they stay readable.
    every = max(1, int(np.ceil(n / 40)))
    ticks = np.arange(0, n, every)
    text = [str(labels[t]) for t in ticks]
    size = 8 if n <= 20 else 6
    axes.set_xticks(ticks, text, rotation=90 if n > 10 else 0, fontsize=size)
    axes.set_yticks(ticks, text, fontsize=size)
    axes.set_xlabel("region b (to)")
    axes.set_ylabel("region a (from)")
    axes.set_title(title, fontsize=10)
    bar = figure.colorbar(image, ax=axes, fraction=0.05, pad=0.03)
    bar.set_label(unit)
    return png_bytes(figure)

"""Region names for connectivity: label lookups as the field writes them
(BIDS ``dseg.tsv`` tables, FreeSurfer colour lookup tables, dicts), and
connectivity as pandas tables.

The missing value of every connectivity output is "no value": NaN in
Python (NumPy and pandas), ``n/a`` in the TSV table of ``stvd
connectivity`` (BIDS's missing value; pandas reads it as NaN) and ``nan``
in its CSV matrices (a number to ``numpy.loadtxt`` and MRtrix). It stands on
the diagonal (a region is not measured against itself) and for every pair
that is not connected inside the domain."""

import os

import numpy as np

MEASURES = ("geodesic_mm", "path_mm", "straight_mm", "connectivity")


def _label_value(text, where):
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{where}: '{text}' is not a label value") from None
    if not np.isfinite(value) or value != round(value):
        raise ValueError(f"{where}: '{text}' is not an integer label value")
    return int(value)


def read_label_names(lookup):
    """Label value -> region name, from ``lookup``: a dict (or any mapping
    or sequence of pairs), or a file: a TSV table with a header row holding
    ``index`` and ``name`` columns (BIDS ``*_dseg.tsv``; ``label`` or
    ``value`` for ``index`` also do), or a FreeSurfer colour lookup table
    (``FreeSurferColorLUT.txt`` style: ``value name R G B A`` per line, ``#``
    comments). Raises ValueError naming the file and line."""
    if lookup is None:
        return {}
    if not isinstance(lookup, (str, os.PathLike)):
        items = lookup.items() if hasattr(lookup, "items") else lookup
        return {_label_value(str(k), "label_names"): str(v) for k, v in items}
    from ._files import read_regular_text

    path = os.fspath(lookup)
    text = read_regular_text(path, 64 << 20)  # a regular file only (never a FIFO), at most 64 MiB
    lines = [(n + 1, line) for n, line in enumerate(text.splitlines())]
    content = [(n, line) for n, line in lines if line.strip() and not line.lstrip().startswith("#")]
    if not content:
        raise ValueError(f"{path}: no region names (an empty lookup table)")
    first = content[0][1]
    names = {}
    if "\t" in first and not first.split("\t")[0].strip().lstrip("-").isdigit():
        header = [cell.strip() for cell in first.split("\t")]
        key = next((c for c in ("index", "label", "value") if c in header), None)
        if key is None or "name" not in header:
            raise ValueError(f"{path}, line {content[0][0]}: a TSV lookup needs the columns index and name "
                             f"(BIDS dseg.tsv), got {', '.join(header)}")
        for n, line in content[1:]:
            cells = [cell.strip() for cell in line.split("\t")]
            if len(cells) != len(header):
                raise ValueError(f"{path}, line {n}: {len(cells)} cells, but the header has {len(header)} columns")
            row = dict(zip(header, cells))
            names[_label_value(row[key], f"{path}, line {n}")] = row["name"]
    else:  # FreeSurfer: value name R G B A
        for n, line in content:
            cells = line.split()
            if len(cells) < 2:
                raise ValueError(f"{path}, line {n}: expected 'value name [R G B A]'")
            names[_label_value(cells[0], f"{path}, line {n}")] = cells[1]
    return names


def region_names(labels, names):
    """One name per label: the lookup's, or the label value as text."""
    return [names.get(int(label), str(int(label))) for label in labels]


def _pandas():
    try:
        import pandas
    except ImportError:
        raise ImportError("connectivity tables need pandas (Debian: python3-pandas)") from None
    return pandas


def long_table(c):
    """One row per ordered pair (a, b), a != b, as ``stvd connectivity``
    writes its table: region_a, region_b, name_a, name_b, the four measures
    (NaN where b is not reachable from a), voxels_a, voxels_b."""
    pandas = _pandas()
    n = len(c.labels)
    a, b = [x.ravel() for x in np.meshgrid(np.arange(n), np.arange(n), indexing="ij")]
    keep = a != b
    a, b = a[keep], b[keep]
    labels, voxels, names = np.asarray(c.labels), np.asarray(c.voxels), np.array(c.names, dtype=object)
    columns = {"region_a": labels[a], "region_b": labels[b], "name_a": names[a], "name_b": names[b]}
    for measure in MEASURES:
        columns[measure] = np.asarray(getattr(c, measure))[a, b]
    columns["voxels_a"], columns["voxels_b"] = voxels[a], voxels[b]
    return pandas.DataFrame(columns)


def square_table(c, measure):
    """The n x n matrix of ``measure``, rows and columns by region name
    (row a measured from region a); NaN on the diagonal and where b is not
    reachable from a."""
    pandas = _pandas()
    if measure not in MEASURES:
        raise ValueError(f"measure: '{measure}' is not one of {', '.join(MEASURES)}")
    index = pandas.Index(c.names, name="region_a")
    columns = pandas.Index(c.names, name="region_b")
    return pandas.DataFrame(np.array(getattr(c, measure), dtype=np.float64), index=index, columns=columns)

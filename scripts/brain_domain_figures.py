#!/usr/bin/env python3
"""The domain-connectivity figures on the shipped brain (docs/cli.md,
docs/benchmarks.md): what --domain-connectivity 6, 18 and 26 change at
--fa-threshold 0.2 and 0.3, whether Dijkstra, STVD and Lanthier reach the
same voxels, and how far the default STVD lies from Lanthier M = 8.

    python3 scripts/brain_domain_figures.py [BUILD_DIR] [OUT_DIR]

BUILD_DIR (default build) must hold tools/stvd; the distance maps go to
OUT_DIR (default out/brain_domain), the tables to stdout as Markdown. The
Lanthier M = 8 run takes several minutes; STVD_BRAIN_LANTHIER_M sets M.
Run it under nice on a shared machine.

The reference for the connectivity figures is connectivity 26 of the same
build: it joins every step of the 26-neighbourhood between two domain
voxels, which is what stvd did before the domain's region was defined (for
Dijkstra on the 26-neighbourhood the distances are the same bit for bit).
"""
import os
import subprocess
import sys

import nibabel
import numpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "sample_data", "dti_philips_biobank")
TENSORS = os.path.join(DATA, "dti_tensor_dipy5d.nii.gz")
SEED = "55,54,15"  # CC_body in seeds.tsv


_maps = {}


def distance_map(stvd, out_dir, name, options):
    """Runs stvd distance (once per name and run) and returns the map, NaN
    where not reached."""
    if name not in _maps:
        path = os.path.join(out_dir, name + ".nii.gz")
        command = [stvd, "distance", TENSORS, "--seed-voxel", SEED, "-o", path, "--unreachable-value", "nan",
                   "-q"] + options
        subprocess.run(command, check=True)
        _maps[name] = numpy.asarray(nibabel.load(path).dataobj, dtype=numpy.float64)
    return _maps[name]


def reached(d):
    return numpy.isfinite(d)


def change_row(label, d, reference):
    """How d differs from the reference map."""
    both = reached(d) & reached(reference) & (reference > 0)
    rise = d[both] / reference[both] - 1.0
    lost = int(numpy.count_nonzero(reached(reference) & ~reached(d)))
    gained = int(numpy.count_nonzero(reached(d) & ~reached(reference)))
    median_change = numpy.median(d[reached(d)]) / numpy.median(reference[reached(reference)]) - 1.0
    return (f"| {label} | {numpy.count_nonzero(reached(d)):,} | {lost:,}" + (f" (+{gained:,})" if gained else "") +
            f" | {100 * median_change:+.2f} % | {100 * numpy.mean(rise > 0.01):.1f} % |"
            f" {100 * numpy.mean(rise > 0.10):.1f} % | {100 * rise.max():.0f} % |")


def deviation_row(label, d, reference):
    """Relative deviation of d from the reference where both are reached (the seed left out)."""
    both = reached(d) & reached(reference) & (reference > 0)
    r = d[both] / reference[both] - 1.0
    p5, median, p95 = numpy.percentile(r, [5, 50, 95])
    return (f"| {label} | {numpy.count_nonzero(both):,} | {100 * median:+.2f} % | {100 * p5:+.2f} % |"
            f" {100 * p95:+.2f} % |")


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    out_dir = sys.argv[2] if len(sys.argv) > 2 else os.path.join("out", "brain_domain")
    stvd = os.path.join(build, "tools", "stvd")
    lanthier_m = os.environ.get("STVD_BRAIN_LANTHIER_M", "8")
    os.makedirs(out_dir, exist_ok=True)
    methods = {"dijkstra": ["--method", "dijkstra"], "stvd": []}

    print("### What the domain connectivity changes (reference: connectivity 26)\n")
    for threshold in ("0.2", "0.3"):
        print(f"FA > {threshold}:\n")
        print("| method, connectivity | reached | unreachable vs 26 | median distance | rose > 1 % | rose > 10 % |"
              " largest rise |")
        print("|---|---|---|---|---|---|---|")
        for method, options in methods.items():
            maps = {c: distance_map(stvd, out_dir, f"{method}_fa{threshold}_c{c}",
                                    options + ["--fa-threshold", threshold, "--domain-connectivity", c])
                    for c in ("6", "18", "26")}
            for c in ("6", "18", "26"):
                print(change_row(f"{'Dijkstra-26' if method == 'dijkstra' else 'STVD (default)'}, {c}", maps[c],
                                 maps["26"]))
        print()

    print("### One domain for every method (FA > 0.2)\n")
    print("| connectivity | Dijkstra-26 | STVD (default) | Lanthier M = 1 | Lanthier M = " + lanthier_m + " | same voxels |")
    print("|---|---|---|---|---|---|")
    lanthier = {}
    for c in ("6", "18", "26"):
        d = distance_map(stvd, out_dir, f"dijkstra_fa0.2_c{c}",
                         ["--method", "dijkstra", "--fa-threshold", "0.2", "--domain-connectivity", c])
        s = distance_map(stvd, out_dir, f"stvd_fa0.2_c{c}", ["--fa-threshold", "0.2", "--domain-connectivity", c])
        coarse = distance_map(stvd, out_dir, f"lanthier1_fa0.2_c{c}",
                              ["--method", "lanthier", "--steiner", "1", "--fa-threshold", "0.2",
                               "--domain-connectivity", c])
        maps = [d, s, coarse]
        fine = "not run"
        if c == "6":
            lanthier[c] = distance_map(stvd, out_dir, f"lanthier{lanthier_m}_fa0.2_c{c}",
                                       ["--method", "lanthier", "--steiner", lanthier_m, "--fa-threshold", "0.2",
                                        "--domain-connectivity", c])
            maps.append(lanthier[c])
            fine = f"{numpy.count_nonzero(reached(lanthier[c])):,}"
        same = all(numpy.array_equal(reached(m), reached(d)) for m in maps)
        print(f"| {c} | {numpy.count_nonzero(reached(d)):,} | {numpy.count_nonzero(reached(s)):,} |"
              f" {numpy.count_nonzero(reached(coarse)):,} | {fine} | {'yes' if same else 'NO'} |")
    print()

    print(f"### Deviation from Lanthier M = {lanthier_m} (FA > 0.2, connectivity 6)\n")
    print("| method | voxels | median | 5th percentile | 95th percentile |")
    print("|---|---|---|---|---|")
    reference = lanthier["6"]
    print(deviation_row("STVD (default: k = 6, segment measure)",
                        distance_map(stvd, out_dir, "stvd_fa0.2_c6", ["--fa-threshold", "0.2"]), reference))
    for measure in ("largest", "projection"):
        print(deviation_row(f"STVD k = 6, {measure} chain measure",
                            distance_map(stvd, out_dir, f"stvd_{measure}_fa0.2_c6",
                                         ["--fa-threshold", "0.2", "--chain-measure", measure]), reference))
    print(deviation_row("Dijkstra-26", distance_map(stvd, out_dir, "dijkstra_fa0.2_c6",
                                                    ["--method", "dijkstra", "--fa-threshold", "0.2"]), reference))
    print(deviation_row("Lanthier M = 1", distance_map(stvd, out_dir, "lanthier1_fa0.2_c6",
                                                       ["--method", "lanthier", "--steiner", "1",
                                                        "--fa-threshold", "0.2"]), reference))


if __name__ == "__main__":
    main()

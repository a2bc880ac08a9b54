#!/usr/bin/env python3
"""From raw diffusion MRI to geodesic distances and paths, in one script.

1. Fits diffusion tensors to the shipped DWI with DIPY (as the sample data's
   PROVENANCE.md describes: b-values below 50 count as 0, median_otsu brain
   mask, weighted least squares).
2. Computes the anisotropic geodesic distance from a seed in the body of the
   corpus callosum with stvd.
3. Traces the geodesic paths from a few targets back to the seed and saves
   them as a TrackVis .trk file on the image's grid.
4. Draws an axial and a coronal slice of the distance map over FA, with the
   paths projected on top, into a PNG.

Run from the top of the repository, after `bash scripts/demo.sh`:

    PYTHONPATH=build/python python3 examples/python/cc_distance_paths.py out/python_example

It writes cc_body_distance.nii.gz, cc_paths.trk and cc_distance_paths.png
into the folder given (default out/python_example). With --mask FILE it takes
that brain mask instead of computing one (median_otsu takes about 20 s).
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.io.gradients import read_bvals_bvecs
from dipy.reconst.dti import TensorModel
from dipy.segment.mask import median_otsu

import stvd

SAMPLE = pathlib.Path(__file__).resolve().parents[2] / "sample_data" / "dti_philips_biobank"
SEED = (55, 54, 15)  # CC_body in seeds.tsv
TARGETS = {  # seeds.tsv
    "CC_body_L_lateral": (62, 54, 18),
    "CC_body_R_lateral": (49, 54, 16),
    "CC_genu": (55, 75, 9),
    "CC_splenium": (55, 41, 8),
    "CST_L_high": (66, 46, 20),
    "CST_R_high": (43, 60, 23),
}


def fit_tensors(mask_path=None):
    """DIPY's tensor fit of the raw data: tensors as (X, Y, Z, 3, 3) in the
    voxel frame (the b-vectors are given along the image axes), FA, the mask
    and the image's affine."""
    dwi = nib.load(SAMPLE / "dwi.nii.gz")
    data = dwi.get_fdata()
    bvals, bvecs = read_bvals_bvecs(str(SAMPLE / "dwi.bval"), str(SAMPLE / "dwi.bvec"))
    bvals[bvals < 50] = 0
    gtab = gradient_table(bvals, bvecs, b0_threshold=50)
    if mask_path:
        mask = np.asanyarray(nib.load(mask_path).dataobj) > 0
    else:
        _, mask = median_otsu(data, vol_idx=np.flatnonzero(gtab.b0s_mask), median_radius=4, numpass=4)
    fit = TensorModel(gtab, fit_method="WLS").fit(data, mask=mask)
    return fit.quadratic_form, fit.fa, mask, dwi


def draw(distance, fa, paths, affine, path):
    """An axial (k = seed) and a coronal (j = seed) slice: FA in grey, the
    distance in colour with 10 mm contours, the paths projected on top."""
    shown = np.where(distance >= 0, distance, np.nan)
    index_of = np.linalg.inv(affine)
    voxel_size = np.linalg.norm(affine[:3, :3], axis=0)
    figure, axes = plt.subplots(1, 2, figsize=(11, 4.8), gridspec_kw={"width_ratios": [112, 112]})
    views = [("axial, k = %d" % SEED[2], (slice(None), slice(None), SEED[2]), (0, 1), "anterior"),
             ("coronal, j = %d" % SEED[1], (slice(None), SEED[1], slice(None)), (0, 2), "superior")]
    for ax, (title, cut, (u, v), up) in zip(axes, views):
        ax.imshow(fa[cut].T, origin="lower", cmap="gray", vmin=0, vmax=1, interpolation="nearest")
        image = ax.imshow(shown[cut].T, origin="lower", cmap="viridis", alpha=0.5, vmin=0,
                          vmax=np.nanmax(shown), interpolation="nearest")
        ax.contour(shown[cut].T, levels=np.arange(10, np.nanmax(shown), 10), colors="white", linewidths=0.5)
        for line in paths:
            ijk = nib.affines.apply_affine(index_of, line)
            ax.plot(ijk[:, u], ijk[:, v], color="red", linewidth=1.4)
        ax.plot(SEED[u], SEED[v], "w*", markersize=10)
        ax.set_title(title)
        ax.set_xlabel("i (toward the patient's left)")
        ax.set_ylabel("j (toward anterior)" if up == "anterior" else "k (toward superior)")
        ax.set_aspect(voxel_size[v] / voxel_size[u])  # millimetres on both axes
        inside = np.argwhere(np.isfinite(shown[cut]))  # the brain, with a margin
        extent = shown[cut].shape
        ax.set_xlim(max(inside[:, 0].min() - 3, -0.5), min(inside[:, 0].max() + 3, extent[0] - 0.5))
        ax.set_ylim(max(inside[:, 1].min() - 3, -0.5), min(inside[:, 1].max() + 3, extent[1] - 0.5))
    figure.colorbar(image, ax=axes, label="geodesic distance from CC_body (mm)", shrink=0.85)
    figure.suptitle("Geodesic distance over FA, with the geodesic paths to six targets (projected)")
    figure.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default="out/python_example", help="output folder")
    parser.add_argument("--mask", help="a brain mask to use instead of median_otsu's")
    args = parser.parse_args()
    output = pathlib.Path(args.output)
    output.mkdir(parents=True, exist_ok=True)

    tensors, fa, mask, dwi = fit_tensors(args.mask)
    print(f"fitted {int(mask.sum()):,} voxels with DIPY")

    result = stvd.propagate(tensors, SEED, affine=dwi.affine, mask=mask)
    image = result.distance_map()  # a NiBabel image with the DWI's affine: float32, -1 where not reached
    nib.save(image, output / "cc_body_distance.nii.gz")
    distance = np.asanyarray(image.dataobj)
    reached = distance >= 0
    print(f"{result.method_text}: reached {int(reached.sum()):,} voxels, "
          f"median {np.median(distance[reached]):.1f} mm, farthest {distance.max():.1f} mm")

    paths = stvd.trace_paths(result, list(TARGETS.values()))
    nib.streamlines.save(stvd.tractogram(paths), str(output / "cc_paths.trk"), header=paths.trk_header())
    for name, geodesic, length, fa_mean in zip(TARGETS, paths.geodesic_mm, paths.euclidean_mm, paths.mean_fa):
        print(f"  {name:18s} geodesic {geodesic:5.1f} mm, length {length:5.1f} mm, mean FA {fa_mean:.2f}")

    draw(distance, fa, paths, dwi.affine, output / "cc_distance_paths.png")
    print(f"wrote {output / 'cc_body_distance.nii.gz'}, {output / 'cc_paths.trk'} and "
          f"{output / 'cc_distance_paths.png'}")


if __name__ == "__main__":
    main()

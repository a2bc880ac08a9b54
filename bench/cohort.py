"""Times cohort runs (not a test): the synthetic cohort of
tests/python/synthetic_cohort.py at the shipped resolution, run serially in
one process (the package's calls, no Dask), on an embedded LocalCluster of 1
and of 2 workers (cluster start-up included), and on an already running
cluster of 1 worker (the Dask layer alone), all without QC pages; the serial
run once more with them (their cost); then one subject resampled to 1.25 mm
isotropic, for the planning figures of docs/cohorts.md.

    PYTHONPATH=build/python python3 bench/cohort.py [--subjects 16] [--folder DIR]
"""

import argparse
import json
import os
import pathlib
import shutil
import sys
import tempfile
import time

import nibabel as nib
import numpy as np

REPOSITORY = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPOSITORY / "tests" / "python"))

import stvd.cohort  # noqa: E402
from synthetic_cohort import make_cohort  # noqa: E402


def timed(label, manifest, outdir, report=False, **options):
    shutil.rmtree(outdir, ignore_errors=True)
    start = time.perf_counter()
    result = stvd.cohort.run(manifest, outdir, report=report, **options)
    seconds = time.perf_counter() - start
    ok = len(result.subjects) - len(result.failed)
    tasks = [json.loads(p.read_text()) for p in pathlib.Path(outdir).glob("*/run.json")]
    compute = sum(t["seconds"] for t in tasks)
    peak = max(t["worker_peak_rss_mib"] for t in tasks)
    print(f"{label:34s} {seconds:7.2f} s  {60 * len(result.subjects) / seconds:6.1f} subjects/min  "
          f"compute in tasks {compute:6.2f} s ({compute / ok:.2f} s per complete subject)  "
          f"peak RSS per worker {peak:.0f} MiB", flush=True)
    return seconds, compute, result


def resampled_subject(source, folder, voxel_mm):
    """The base subject resampled to ``voxel_mm`` isotropic (trilinear
    tensors, nearest mask and labels, the seeds moved with the grid)."""
    from scipy import ndimage

    folder.mkdir(parents=True, exist_ok=True)
    factor = [z / voxel_mm for z in nib.load(source / "mask.nii.gz").header.get_zooms()[:3]]
    for name, order in (("tensors", 1), ("mask", 0), ("labels", 0)):
        image = nib.load(source / f"{name}.nii.gz")
        data = np.asanyarray(image.dataobj)
        if data.ndim == 5:
            out = np.stack([ndimage.zoom(data[:, :, :, 0, c], factor, order=order) for c in range(6)], -1)
            out = out[:, :, :, np.newaxis, :].astype(np.float32)
        else:
            out = ndimage.zoom(data, factor, order=order)
        affine = image.affine.copy()
        affine[:3, :3] = affine[:3, :3] / np.array(factor)
        header = image.header.copy()
        header.set_data_dtype(out.dtype)
        nib.save(nib.Nifti1Image(out, affine, header), folder / f"{name}.nii.gz")
    lines = (source / "seeds.tsv").read_text().splitlines()
    seeds = [lines[0]] + ["\t".join([c[0]] + [str(int(round(int(v) * f))) for v, f in zip(c[1:4], factor)])
                          for c in (line.split("\t") for line in lines[1:])]
    (folder / "seeds.tsv").write_text("\n".join(seeds) + "\n")
    manifest = folder.parent / "manifest_hires.tsv"
    manifest.write_text("subject\ttensors\tlabels\tmask\tseeds\n"
                        f"{folder.name}\t{folder.name}/tensors.nii.gz\t{folder.name}/labels.nii.gz\t"
                        f"{folder.name}/mask.nii.gz\t{folder.name}/seeds.tsv\n")
    return manifest, out.shape[:3]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--subjects", type=int, default=16)
    parser.add_argument("--folder", help="where to build the cohort and write (default: a temporary folder)")
    args = parser.parse_args()
    root = pathlib.Path(args.folder or tempfile.mkdtemp(prefix="stvd-cohort-bench-"))
    manifest = make_cohort(root / "data", subjects=args.subjects)
    print(f"{args.subjects} subjects at the shipped resolution in {root}; {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.1f}", flush=True)
    import matplotlib

    matplotlib.use("Agg")

    serial, compute, result = timed("serial, one process, no Dask", manifest, root / "serial", serial=True)
    with_pages, _, _ = timed("serial, with QC pages and index", manifest, root / "pages", serial=True, report=True)
    one, _, _ = timed("LocalCluster, 1 worker (start-up in)", manifest, root / "dask1", workers=1)
    two, _, _ = timed("LocalCluster, 2 workers (start-up in)", manifest, root / "dask2", workers=2)
    from distributed import Client, LocalCluster

    # This machine's loopback only, HTTP servers included (":0" would be
    # every interface), as the embedded cluster of stvd.cohort.run.
    local = dict(threads_per_worker=1, host="127.0.0.1", dashboard_address="127.0.0.1:0",
                 worker_dashboard_address="127.0.0.1:0")
    with LocalCluster(n_workers=1, **local) as cluster, Client(cluster) as c:
        running, running_compute, _ = timed("running cluster, 1 worker", manifest, root / "running", client=c)
    with LocalCluster(n_workers=2, **local) as cluster, Client(cluster) as c:
        running2, _, _ = timed("running cluster, 2 workers", manifest, root / "running2", client=c)
    complete = len(result.subjects) - len(result.failed)
    print(f"throughput, 2 workers / serial: embedded {serial / two:.2f}x, running cluster {serial / running2:.2f}x")
    print(f"Dask layer on a running 1-worker cluster: {(running - serial) / len(result.subjects):.3f} s per subject, "
          f"{100 * (running - serial) / serial:.1f} % of the serial run "
          f"(compute per complete subject {compute / complete:.2f} s)")
    stored = sum(p.stat().st_size for p in (root / "serial").rglob("*") if p.is_file()) / complete
    print(f"outputs per subject: {stored / 1e6:.2f} MB; QC pages: {(with_pages - serial) / complete:.2f} s and "
          f"{sum(p.stat().st_size for p in (root / 'pages').rglob('*.html')) / complete / 1e6:.2f} MB per subject")

    hires_manifest, shape = resampled_subject(root / "data" / "base", root / "data" / "base_1.25mm", 1.25)
    hires, hires_compute, hires_result = timed(f"1.25 mm subject {shape}, serial", hires_manifest, root / "hires",
                                               serial=True)
    assert not hires_result.failed, hires_result.subjects
    hires_stored = sum(p.stat().st_size for p in (root / "hires").rglob("*") if p.is_file())
    print(f"load average at the end: {' '.join(f'{v:.1f}' for v in os.getloadavg())}")
    for label, per_subject, size in (("shipped 2 mm", compute / complete, stored),
                                     ("1.25 mm", hires_compute, hires_stored)):
        print(f"40,000 subjects at {label}: {40000 * per_subject / 3600:.0f} core-hours, "
              f"{40000 * size / 1e9:.0f} GB of outputs")


if __name__ == "__main__":
    main()

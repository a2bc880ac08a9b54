#!/usr/bin/env python3
"""stvd against Hamiltonian Fast Marching on the exact-metric phantoms.

HFM (J.-M. Mirebeau's HamiltonFastMarching) is not a dependency of stvd
and none of its code is here: build its file interface yourself (the
FileHFM_Riemann3 executable of its Interfaces/FileHFM, with CMake) and
point --hfm at it. This script writes each phantom once
(`stvd_evaluation phantom`: the metric as a NRRD tensor file, the exact
distances, the seed), runs `stvd distance` on it and HFM on the same
tensors (orders 1 and 2, without and with source factoring), each as a
whole process, alternating, and compares every result with the exact
distances over the voxels more than 3 voxels from the seed.

    hfm_comparison.py --hfm FileHFM_Riemann3 --hfm-commit SHA --stvd build/tools/stvd
                      --evaluation build/bench/stvd_evaluation [--sizes 64,128]
                      [--scenes curved,constant,rotated25,rotated625] [--repeats 3]
                      --out docs/benchmarks/hfm_comparison.tsv

The TSV starts with `#` lines saying when, where and with which HFM commit
it was measured; scripts/evaluation_report.py puts it into
docs/benchmarks.md. Needs NumPy only (it reads HFM's file format and the
tool's uncompressed NIfTI output itself).
"""
import argparse
import os
import resource
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np


def write_hfm_input(params, prefix):
    """HFM's file interface: PREFIX_Format.txt (key, rank, dimensions) and
    PREFIX_Data.dat (the numbers as float64, in the order of the keys)."""
    data = []
    with open(prefix + "_Format.txt", "w") as f:
        for key, value in params.items():
            if isinstance(value, str):
                f.write(f"{key}\n-1\n{value}\n\n")
            elif np.isscalar(value):
                f.write(f"{key}\n0\n\n")
                data.append(np.array([value], dtype="d"))
            else:
                value = np.asarray(value, dtype="d")
                f.write(f"{key}\n{value.ndim}\n" + "".join(f"{d}\n" for d in value.shape) + "\n")
                data.append(value.ravel())
    np.concatenate(data).astype("d").tofile(prefix + "_Data.dat")


def read_hfm_output(prefix):
    data = np.fromfile(prefix + "_Data.dat")
    position, out = 0, {}
    with open(prefix + "_Format.txt") as f:
        while True:
            key = f.readline().strip()
            if not key:
                break
            rank = int(f.readline())
            if rank == -1:
                out[key] = f.readline().strip()
            elif rank == 0:
                out[key] = data[position]
                position += 1
            else:
                dims = [int(f.readline()) for _ in range(rank)]
                size = int(np.prod(dims))
                out[key] = data[position:position + size].reshape(dims)
                position += size
            f.readline()
    return out


def read_nifti_float32(path):
    """The voxels of an uncompressed NIfTI-1 float32 image, x fastest."""
    with open(path, "rb") as f:
        header = f.read(352)
    if struct.unpack("<i", header[:4])[0] != 348:
        raise ValueError(f"{path}: not a little-endian NIfTI-1 file")
    dims = struct.unpack("<8h", header[40:56])
    datatype = struct.unpack("<h", header[70:72])[0]
    offset = int(struct.unpack("<f", header[108:112])[0])
    if datatype != 16:
        raise ValueError(f"{path}: datatype {datatype}, expected float32")
    shape = dims[1:1 + dims[0]]
    values = np.fromfile(path, dtype="<f4", offset=offset, count=int(np.prod(shape)))
    return values.reshape(shape[::-1])  # [k][j][i]


class Phantom:
    def __init__(self, evaluation, scene, n, folder):
        self.scene, self.n = scene, n
        prefix = os.path.join(folder, f"{scene}_{n}")
        subprocess.run([evaluation, "phantom", "--scene", scene, "--size", str(n), "--out", prefix], check=True)
        self.nrrd = prefix + ".nrrd"
        with open(self.nrrd, "rb") as f:
            raw = f.read()
        body = raw[raw.index(b"\n\n") + 2:]
        g = np.frombuffer(body, dtype="<f4").reshape(n, n, n, 6)  # [k][j][i][xx xy xz yy yz zz]
        self.tensors = g
        self.exact = np.fromfile(prefix + ".exact").reshape(n, n, n)  # [k][j][i]
        self.seed = [int(x) for x in open(prefix + ".seed").read().split()]
        k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
        radius = np.sqrt((i - self.seed[0]) ** 2 + (j - self.seed[1]) ** 2 + (k - self.seed[2]) ** 2)
        self.far = (self.exact > 0) & (radius > 3)

    def errors(self, distance):
        """Mean, 99th percentile and largest relative error, and the voxels
        not reached, over the voxels more than 3 voxels from the seed."""
        d, x = distance[self.far], self.exact[self.far]
        reached = np.isfinite(d) & (d >= 0)
        e = np.sort(np.abs(d[reached] - x[reached]) / x[reached])
        return e.mean(), e[(len(e) - 1) * 99 // 100], e[-1], int((~reached).sum())


def timed(command):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    result = subprocess.run(command, capture_output=True, text=True)
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        sys.exit(f"hfm_comparison.py: {' '.join(command)} failed:\n{result.stdout}\n{result.stderr}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def run_stvd(tool, phantom, folder):
    out = os.path.join(folder, "stvd.nii")
    wall, cpu = timed([tool, "distance", phantom.nrrd, "--tensor-kind", "metric", "--seed-voxel",
                       ",".join(map(str, phantom.seed)), "-o", out, "-q"])
    return wall, cpu, read_nifti_float32(out).astype("d")


def run_hfm(hfm, phantom, folder, order, factoring):
    g = phantom.tensors.astype("d")
    # HFM: row-major [i][j][k], components xx, xy, yy, xz, yz, zz.
    metric = np.transpose(g, (2, 1, 0, 3))[..., [0, 1, 3, 2, 4, 5]]
    n = phantom.n
    params = {"model": "Riemann3", "arrayOrdering": "RowMajor", "dims": np.array([n, n, n], "d"),
              "gridScale": 1.0, "origin": np.zeros(3), "metric": metric,
              "seeds": np.array([[s + 0.5 for s in phantom.seed]]), "order": float(order),
              "exportValues": 1.0}
    if factoring:
        params["factoringRadius"] = float(factoring)
    prefix_in, prefix_out = os.path.join(folder, "hfm_in"), os.path.join(folder, "hfm_out")
    write_hfm_input(params, prefix_in)
    wall, cpu = timed([hfm, prefix_in, prefix_out])
    values = read_hfm_output(prefix_out)["values"]  # [i][j][k]
    return wall, cpu, np.transpose(values, (2, 1, 0))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--hfm", required=True)
    parser.add_argument("--hfm-commit", required=True)
    parser.add_argument("--stvd", required=True)
    parser.add_argument("--evaluation", required=True)
    parser.add_argument("--sizes", default="64,128")
    parser.add_argument("--scenes", default="curved,constant,rotated25,rotated625")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", required=True)
    a = parser.parse_args()
    rows = []
    with open("/proc/loadavg") as f:
        load_start = " ".join(f.read().split()[:3])
    variants = [("stvd", "default", None, None),
                ("HFM", "order 1", 1, 0), ("HFM", "order 1, factoring radius 10", 1, 10),
                ("HFM", "order 2", 2, 0), ("HFM", "order 2, factoring radius 10", 2, 10),
                ("HFM", "order 2, factoring everywhere", 2, -1)]
    with tempfile.TemporaryDirectory() as folder:
        for n in map(int, a.sizes.split(",")):
            for scene in a.scenes.split(","):
                phantom = Phantom(a.evaluation, scene, n, folder)
                times = {v: [] for v in variants}
                last = {}
                for _ in range(a.repeats):  # alternating: each round runs every variant once
                    for v in variants:
                        tool, _, order, factoring = v
                        if tool == "stvd":
                            wall, cpu, d = run_stvd(a.stvd, phantom, folder)
                        else:
                            wall, cpu, d = run_hfm(a.hfm, phantom, folder, order, factoring)
                        times[v].append((wall, cpu))
                        last[v] = d
                for v in variants:
                    mean, p99, worst, unreached = phantom.errors(last[v])
                    wall = sorted(t[0] for t in times[v])[len(times[v]) // 2]
                    cpu = sorted(t[1] for t in times[v])[len(times[v]) // 2]
                    rows.append((scene, n, v[0], v[1], mean, p99, worst, unreached, wall, cpu))
                    print(f"{scene:10s} {n:4d} {v[0]:4s} {v[1]:30s} mean {100 * mean:8.4f} % p99 {100 * p99:7.3f} % "
                          f"max {100 * worst:7.2f} % unreached {unreached:5d} | process {wall:.2f} s wall "
                          f"{cpu:.2f} s CPU", flush=True)
    with open("/proc/loadavg") as f:
        load_end = " ".join(f.read().split()[:3])
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    with open(a.out, "w") as f:
        f.write(f"# date={time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n")
        f.write(f"# stvd_commit={commit}\n# hfm_commit={a.hfm_commit}\n")
        f.write(f"# load_start={load_start}\n# load_end={load_end}\n# repeats={a.repeats}\n")
        f.write("scene\tn\ttool\tvariant\tmean_rel_error_far\tp99_rel_error_far\tmax_rel_error_far\t"
                "unreached\tprocess_wall_seconds\tprocess_cpu_seconds\n")
        for r in rows:
            f.write("\t".join(str(x) if not isinstance(x, float) else f"{x:.6g}" for x in r) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Timings of the Python package on the shipped brain (docs/python.md).

overhead: stvd.distance against the `stvd` tool, both from the DIPY tensor
    file with the default options and the CC_body seed. The tool's own phase
    timings (--stats) give its read, metric and propagation seconds; the
    Python call is timed inside one interpreter (start-up and import
    excluded), from a path, a NiBabel image (loading included) and an array
    in memory. Runs alternate between the two.
threads: two distance maps computed one after the other, and by two Python
    threads at once; the ratio of the wall times, several times over, with
    the load average of the machine.

    PYTHONPATH=build/python python3 bench/python_package.py overhead --repeats 9
    PYTHONPATH=build/python python3 bench/python_package.py threads --repeats 7
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import tempfile
import threading
import time

import nibabel as nib
import numpy as np

import stvd

ROOT = pathlib.Path(__file__).resolve().parents[1]
TENSORS = ROOT / "sample_data" / "dti_philips_biobank" / "dti_tensor_dipy5d.nii.gz"
SEED = (55, 54, 15)
SEEDS = [SEED, (68, 50, 11), (41, 51, 12), (55, 41, 8)]


def load():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def spread(values):
    return f"median {statistics.median(values):.3f} (min {min(values):.3f}, max {max(values):.3f})"


def timed(call):
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def overhead(args):
    tool = pathlib.Path(args.tool)
    image = nib.load(TENSORS)
    components = np.asanyarray(image.dataobj)[:, :, :, 0, :]
    stvd.distance(str(TENSORS), SEED)  # warm up: page cache, allocator
    tool_phases, tool_wall, from_path, from_image, from_array = [], [], [], [], []
    with tempfile.TemporaryDirectory() as scratch:
        stats = pathlib.Path(scratch) / "stats.json"
        for _ in range(args.repeats):
            start = time.perf_counter()
            subprocess.run([str(tool), "distance", str(TENSORS), "--seed-voxel", ",".join(map(str, SEED)), "-o",
                            str(pathlib.Path(scratch) / "d.nii.gz"), "--stats", str(stats), "-q"], check=True)
            tool_wall.append(time.perf_counter() - start)
            tool_phases.append(json.loads(stats.read_text())["seconds"])
            from_path.append(timed(lambda: stvd.distance(str(TENSORS), SEED)))
            from_image.append(timed(lambda: stvd.distance(nib.load(TENSORS), SEED)))
            from_array.append(timed(lambda: stvd.distance(components, SEED, affine=image.affine,
                                                          tensor_order="lower")))
    read = [p["read"] for p in tool_phases]
    propagate = [p["propagate"] for p in tool_phases]
    without_write = [p["read"] + p["metric"] + p["propagate"] for p in tool_phases]
    read_and_propagate = [p["read"] + p["propagate"] for p in tool_phases]
    print(f"load average before: {load()}; {args.repeats} alternating runs; seconds:")
    print(f"  tool read            {spread(read)}")
    print(f"  tool metric          {spread([p['metric'] for p in tool_phases])}")
    print(f"  tool propagation     {spread(propagate)}")
    print(f"  tool write           {spread([p['write'] for p in tool_phases])}")
    print(f"  tool read+metric+propagation {spread(without_write)}")
    print(f"  tool process, wall   {spread(tool_wall)}")
    print(f"  stvd.distance(path)  {spread(from_path)}")
    print(f"  stvd.distance(nib.load(path)) {spread(from_image)}")
    print(f"  stvd.distance(array) {spread(from_array)}")
    pairs = [a / b for a, b in zip(from_path, without_write)]
    print(f"stvd.distance(path) / tool read+metric+propagation of the same round: {spread(pairs)}")
    print(f"medians: {statistics.median(from_path) / statistics.median(without_write):.3f}; "
          f"against read+propagation alone: {statistics.median(from_path) / statistics.median(read_and_propagate):.3f}")
    print(f"load average after: {load()}")


def threads(args):
    image = nib.load(TENSORS)
    components = np.asanyarray(image.dataobj)[:, :, :, 0, :]
    inputs = {
        "path": lambda seed: stvd.distance(str(TENSORS), seed),
        "array": lambda seed: stvd.distance(components, seed, affine=image.affine, tensor_order="lower"),
    }
    for name, compute in inputs.items():
        compute(SEED)
        ratios = []
        print(f"{name} input; load average before: {load()}")
        for round_ in range(args.repeats):
            seeds = SEEDS[round_ % 2 * 2:round_ % 2 * 2 + 2]
            cpu = time.process_time()
            serial = timed(lambda: [compute(s) for s in seeds])
            serial_cores = (time.process_time() - cpu) / serial
            workers = [threading.Thread(target=compute, args=(s,)) for s in seeds]
            cpu = time.process_time()
            start = time.perf_counter()
            for w in workers:
                w.start()
            for w in workers:
                w.join()
            parallel = time.perf_counter() - start
            parallel_cores = (time.process_time() - cpu) / parallel
            ratios.append(parallel / serial)
            # Cores: CPU seconds of the process per wall second; below 1 and
            # 2 the machine gave the process less than it asked for.
            print(f"  one after the other {serial:.3f} s ({serial_cores:.2f} cores), two threads {parallel:.3f} s "
                  f"({parallel_cores:.2f} cores): {parallel / serial:.3f}")
        print(f"  two threads / one after the other: {spread(ratios)}; load average after: {load()}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("what", choices=["overhead", "threads"])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--tool", default=str(ROOT / "build" / "tools" / "stvd"))
    args = parser.parse_args()
    overhead(args) if args.what == "overhead" else threads(args)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Scene.trace's rate against the C++ backend's own rate on the same rays, in one run (issue 19:
>= 0.9x over the 1.48 M-triangle SRTM DEM). docs/python.md, "Benchmark".

    PYTHONPATH=build/python python3 bench/python/trace_rate.py [--rays 1000000] [--threads 1 0]

The rays: an airborne look at the DEM (origins 500 m above its highest point over the middle 80 %
of it, directions within about 27 degrees of nadir, seeded). For each thread count and round, the
script times `scene.trace(origins, directions)` (Python: the arrays in, every field of `Hits`
out) and `scene._intersect_seconds(...)` (C++: Backend::intersect on the same rays, converted
before the clock runs, as `beamtrace bench` times "our" backends); each rate is the best of its
rounds, the rounds alternating so that load from other processes falls on both; the median over
the rounds of each round's C++ time / Python time moves less with such load, and the last column,
the same median of the CPU time the process used during each call (every thread, user and
system), less again: time the threads wait for the cores is not counted. The C++ side writes its
hits into a batch allocated and filled before its clock runs; `trace` allocates its arrays and
touches them first inside the timed call.
Before timing, it checks that both hit the same number of rays. Exit code 1 when a ratio (of the
best rates) is below --min-ratio.
"""

import argparse
import os
import pathlib
import platform
import sys
import time

import numpy as np

import beamtrace

REPO = pathlib.Path(__file__).resolve().parents[2]


def cpu_model():
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def airborne_rays(scene, count, seed):
    (x0, y0, _), (x1, y1, z1) = scene.bounds
    rng = np.random.default_rng(seed)
    cx, cy, hx, hy = (x0 + x1) / 2, (y0 + y1) / 2, 0.4 * (x1 - x0), 0.4 * (y1 - y0)
    origins = np.column_stack([rng.uniform(cx - hx, cx + hx, count),
                               rng.uniform(cy - hy, cy + hy, count),
                               np.full(count, z1 + 500.0)])
    directions = np.column_stack([rng.uniform(-0.5, 0.5, (count, 2)), -np.ones(count)])
    return origins, directions


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", default=str(REPO / "examples" / "scenes" / "srtm_terrain.yaml"))
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--backend", default="bvh")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 0],
                    help="thread counts (0: every hardware thread)")
    ap.add_argument("--repeats", type=int, default=5, help="rounds; each rate is the best")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--min-ratio", type=float, default=0.0,
                    help="exit 1 when Python/C++ is below this (0: report only)")
    args = ap.parse_args()

    t0 = time.perf_counter()
    scene = beamtrace.Scene.load(args.scene)
    origins, directions = airborne_rays(scene, args.rays, args.seed)
    # Builds the backend (kept by the scene) and checks the results before anything is timed.
    hits = scene.trace(origins, directions, backend=args.backend)
    _, cpp_hits, _ = scene._intersect_seconds(origins, directions, backend=args.backend,
                                              repeats=1)
    py_hits = int(np.count_nonzero(hits.face >= 0))
    if py_hits != cpp_hits or py_hits == 0:
        sys.exit(f"trace_rate: Python hit {py_hits} rays, C++ {cpp_hits}: not the same rays")
    print(f"# Scene.trace vs. the C++ backend, {args.backend}, {args.rays} rays "
          f"({py_hits} hit) over {pathlib.Path(args.scene).name} "
          f"({scene.triangle_count} triangles; load + build {time.perf_counter() - t0:.1f} s)")
    print(f"# {cpu_model()}, {os.cpu_count()} hardware threads, best of {args.repeats} rounds")
    print("| threads | Python Mrays/s | C++ Mrays/s | ratio | median ratio of the rounds "
          "| median CPU-time ratio |")
    print("|---|---|---|---|---|---|")
    worst = float("inf")
    for threads in args.threads:
        py, cpp, py_cpu, cpp_cpu = [], [], [], []
        for _ in range(args.repeats):
            cpu_start = time.process_time()
            start = time.perf_counter()
            hits = scene.trace(origins, directions, backend=args.backend, threads=threads)
            py.append(time.perf_counter() - start)
            py_cpu.append(time.process_time() - cpu_start)
            del hits  # freeing the arrays (60 MB for 10^6 rays) is the caller's, not timed
            seconds, _, cpu = scene._intersect_seconds(origins, directions, backend=args.backend,
                                                       threads=threads, repeats=1)
            cpp.append(seconds)
            cpp_cpu.append(cpu)
        ratio = min(cpp) / min(py)
        worst = min(worst, ratio)
        label = threads if threads else f"{os.cpu_count()} (0)"
        print(f"| {label} | {args.rays / min(py) / 1e6:.3g} | {args.rays / min(cpp) / 1e6:.3g} "
              f"| {ratio:.3f} | {np.median(np.array(cpp) / np.array(py)):.3f} "
              f"| {np.median(np.array(cpp_cpu) / np.array(py_cpu)):.3f} |")
    if worst < args.min_ratio:
        sys.exit(f"trace_rate: ratio {worst:.3f} below --min-ratio {args.min_ratio}")


if __name__ == "__main__":
    main()

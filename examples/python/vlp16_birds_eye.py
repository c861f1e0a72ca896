#!/usr/bin/env python3
"""A VLP-16 on a car driving through the demo scene, its points plotted as a bird's-eye image.

    PYTHONPATH=build/python python3 examples/python/vlp16_birds_eye.py [--duration-s 1.0] [--out birds_eye.png]

The survey is a dict (the keys of a survey file, docs/survey.md) run in memory by
beamtrace.run_survey: no file is written but the picture. Each 0.2 m cell shows the highest point
in it. The plot needs matplotlib (Debian: python3-matplotlib); without it the script says so and
exits 0 after the survey.
"""

import argparse
import sys

import numpy as np

import beamtrace

# The terrain 1.8 m up along y = -10 (examples/surveys/car_hdl64.yaml's drive).
DRIVE_M = [[-30, -10, 0.458], [-25, -10, 0.704], [-20, -10, 0.752], [-15, -10, 0.670],
           [-10, -10, 0.624], [-5, -10, 0.796], [0, -10, 1.282], [5, -10, 2.042],
           [10, -10, 2.903], [15, -10, 3.642], [20, -10, 4.080], [25, -10, 4.164],
           [30, -10, 3.987]]


def drive_survey(duration_s):
    """The survey as a dict: a VLP-16 on the car's roof at 10 m/s for duration_s seconds."""
    return {
        "scene": "demo",
        "scanner": {"type": "rotating", "preset": "vlp16", "duration_s": duration_s,
                    "range_min_m": 1.0, "range_max_m": 100},
        "platform": {"type": "legs", "speed_mps": 10, "waypoints_m": DRIVE_M},
        "mount": {"lever_arm_m": [0.5, 0, 0.3]},
    }


def birds_eye(points, cell_m=0.2):
    """The highest z of each cell of a grid over the points' x, y: (rows, cols) float64, NaN where
    no point fell, row 0 at the largest y (north up); and the extent (xmin, xmax, ymin, ymax)."""
    x, y, z = points["x"], points["y"], points["z"]
    x0, y1 = x.min(), y.max()
    cols = int(np.floor((x.max() - x0) / cell_m)) + 1
    rows = int(np.floor((y1 - y.min()) / cell_m)) + 1
    col = np.floor((x - x0) / cell_m).astype(np.int64)
    row = np.floor((y1 - y) / cell_m).astype(np.int64)
    image = np.full(rows * cols, -np.inf)
    np.maximum.at(image, row * cols + col, z)
    image[np.isinf(image)] = np.nan
    return image.reshape(rows, cols), (x0, x0 + cols * cell_m, y1 - rows * cell_m, y1)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration-s", type=float, default=1.0, help="seconds of driving")
    parser.add_argument("--out", default="birds_eye.png", help="the picture (PNG)")
    args = parser.parse_args(argv)

    def progress(done, total):
        print(f"\rsurveying: {done}/{total} pulses", end="", file=sys.stderr, flush=True)

    points = beamtrace.run_survey(drive_survey(args.duration_s), seed=1, progress=progress)
    print(file=sys.stderr)
    image, extent = birds_eye(points)
    print(f"{len(points)} points, {np.count_nonzero(~np.isnan(image))} cells of 0.2 m, "
          f"z {np.nanmin(image):.2f} to {np.nanmax(image):.2f} m")
    try:
        import matplotlib
    except ImportError:
        print("matplotlib is not installed (python3-matplotlib): no plot")
        return 0
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 8))
    shown = ax.imshow(image, extent=extent, cmap="viridis", interpolation="nearest")
    ax.plot(*np.array(DRIVE_M)[:, :2].T, "w--", linewidth=0.8, label="drive")
    ax.set(xlabel="x (m)", ylabel="y (m)", title=f"VLP-16 drive, {len(points)} points")
    fig.colorbar(shown, ax=ax, label="highest z (m)", shrink=0.8)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

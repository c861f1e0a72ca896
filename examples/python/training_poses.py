#!/usr/bin/env python3
"""Training data from randomised scanner poses: one VLP-16 revolution per pose, written as .npy.

    PYTHONPATH=build/python python3 examples/python/training_poses.py [--count 100] [--out training]

Each pose is a survey dict (docs/survey.md) run in memory by beamtrace.run_survey, its seed the
pose's index, so that the same count gives the same files. Writes OUT/scan_0000.npy... (the points:
x, y, z, intensity, classification... see docs/python.md) and OUT/poses.npy (count, 4): x, y, z,
yaw_deg of each pose.
"""

import argparse
import pathlib
import sys

import numpy as np

import beamtrace

# The terrain height along y = -10 in the demo scene (examples/surveys/car_hdl64.yaml).
GROUND_X_M = np.arange(-30, 31, 5)
GROUND_Z_M = np.array([0.458, 0.704, 0.752, 0.670, 0.624, 0.796, 1.282, 2.042, 2.903, 3.642,
                       4.080, 4.164, 3.987]) - 1.8


def random_pose(rng):
    """x, y, z (metres, 1.5-2.5 m above the terrain) and yaw (degrees) near the demo's road."""
    x = rng.uniform(-28, 28)
    y = rng.uniform(-11, -9)
    z = np.interp(x, GROUND_X_M, GROUND_Z_M) + rng.uniform(1.5, 2.5)
    return np.array([x, y, z, rng.uniform(-180, 180)])


def pose_survey(pose):
    x, y, z, yaw = pose
    return {
        "scene": "demo",
        "scanner": {"type": "rotating", "preset": "vlp16", "range_min_m": 0.5,
                    "range_max_m": 100},
        "platform": {"type": "static", "position_m": [x, y, z], "rotate_deg": [0, 0, yaw]},
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=100, help="poses")
    parser.add_argument("--out", default="training", help="output folder")
    parser.add_argument("--threads", type=int, default=0, help="0: every hardware thread")
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(2024)
    poses = np.array([random_pose(rng) for _ in range(args.count)]).reshape(-1, 4)
    total = 0
    for i, pose in enumerate(poses):
        points = beamtrace.run_survey(pose_survey(pose), seed=i, threads=args.threads)
        np.save(out / f"scan_{i:04d}.npy", points)
        total += len(points)
    np.save(out / "poses.npy", poses)
    print(f"{args.count} poses, {total} points in {out}/scan_*.npy")
    return 0


if __name__ == "__main__":
    sys.exit(main())

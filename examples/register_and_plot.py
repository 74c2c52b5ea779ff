#!/usr/bin/env python3
"""Registers a dataset folder with fine2coarse and plots the trajectories from above.

    PYTHONPATH=build/python python3 examples/register_and_plot.py DATASET [--intrinsics tum-fr1] [-o trajectory.png]

T0 (the odometry) and the refined poses, seen from above (x, z), with the ATE in the title when
the folder has ground truth; the poses also go to <output>_poses.txt (one 4 x 4 per line).
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fine2coarse  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dataset")
    parser.add_argument("--intrinsics", help="tum-fr1, tum-fr2, tum-fr3, primesense or fx,fy,cx,cy")
    parser.add_argument("-o", "--output", default="trajectory.png")
    args = parser.parse_args()
    options = {"intrinsics": args.intrinsics} if args.intrinsics else {}

    finished = set()

    def progress(stage, done, total):  # called from the pipeline's threads
        if done == total and stage not in finished:
            finished.add(stage)
            print(f"{stage}: done ({total})")

    r = fine2coarse.register(args.dataset, progress=progress, **options)
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot(r.t0[:, 0, 3], r.t0[:, 2, 3], label="T0 (odometry)", color="tab:orange")
    ax.plot(r.poses[:, 0, 3], r.poses[:, 2, 3], label="fine2coarse", color="tab:blue")
    title = f"{os.path.basename(os.path.normpath(args.dataset))}: {len(r.poses)} frames"
    try:
        e = fine2coarse.evaluate(r.poses, args.dataset, timestamps=r.timestamps)
        title += f", ATE {e['ate_m']['rmse']:.4f} m"
    except fine2coarse.InputError as error:  # no ground truth
        print(f"not evaluated: {error}")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_aspect("equal")
    ax.legend()
    ax.set_title(title)
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")
    np.savetxt(os.path.splitext(args.output)[0] + "_poses.txt", r.poses.reshape(-1, 16))


if __name__ == "__main__":
    main()

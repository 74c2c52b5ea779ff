#!/usr/bin/python3
"""Open3D's reconstruction system (Choi et al., the method the paper compares with) on the
same frames fine2coarse registers, as a peer measured in the same benchmark run.

    /usr/bin/python3 bench/open3d_reconstruction.py INFO_JSON WORK_DIR OUT_LOG

INFO_JSON is `fine2coarse info --json` for the dataset (the selected frames, intrinsics and
depth scale). The frames are linked into WORK_DIR/dataset/{color,depth}/NNNNNN.ext in our
order, so the .log it writes (camera-to-world per frame id) evaluates against the dataset
like ours. It runs Open3D's own `examples/reconstruction_system/run_system.py` (make,
register, refine, integrate: poses and a mesh, as `register` does) from a temporary copy
with one line fixed for NumPy >= 1.24 (`Transform_good[:3, 3:] = t_approx`); its defaults
otherwise (depth_max 3 m, 100 frames per fragment, 5 cm voxels for registration).
Prints one JSON line: seconds, frames, peak memory and the log's path; exits non-zero with the reason.
"""
import json
import os
import resource
import shutil
import subprocess
import sys
import time


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    info_path, work, out_log = sys.argv[1:]
    info = json.load(open(info_path))
    try:
        import open3d  # noqa: F401
        import joblib  # noqa: F401
    except ImportError as e:
        sys.exit(f"open3d peer: {e.name} is not installed (Debian: python3-open3d, python3-joblib)")
    if info["depth_encoding"] != "plain":
        sys.exit("open3d peer: Open3D cannot read this depth encoding (" + info["depth_encoding"] + ")")
    k = info["intrinsics"]
    if k is None:
        sys.exit("open3d peer: the dataset has no intrinsics")

    shutil.rmtree(work, ignore_errors=True)
    dataset = os.path.join(work, "dataset")
    for sub in ("color", "depth"):
        os.makedirs(os.path.join(dataset, sub))
    for i, f in enumerate(info["frames"]):
        ext = os.path.splitext(f["color"])[1]
        os.symlink(os.path.abspath(f["color"]), os.path.join(dataset, "color", f"{i:06d}{ext}"))
        os.symlink(os.path.abspath(f["depth"]), os.path.join(dataset, "depth", f"{i:06d}.png"))
    intrinsic = os.path.join(work, "intrinsic.json")
    json.dump({"width": k["width"], "height": k["height"],
               "intrinsic_matrix": [k["fx"], 0, 0, 0, k["fy"], 0, k["cx"], k["cy"], 1]}, open(intrinsic, "w"))
    config = os.path.join(work, "config.json")
    json.dump({"name": os.path.basename(info["input"].rstrip("/")), "path_dataset": dataset,
               "path_intrinsic": intrinsic, "depth_scale": 1.0 / info["depth_meters_per_unit"],
               "python_multi_threading": True}, open(config, "w"))

    # A private copy of the examples with the NumPy fix.
    import open3d
    examples = os.path.join(os.path.dirname(open3d.__file__), "examples")
    code = os.path.join(work, "code")
    shutil.copytree(os.path.join(examples, "reconstruction_system"), os.path.join(code, "reconstruction_system"))
    shutil.copy(os.path.join(examples, "open3d_example.py"), code)
    pose = os.path.join(code, "reconstruction_system", "opencv_pose_estimation.py")
    src = open(pose).read()
    old = "Transform_good[:3, 3] = [t_approx[0], t_approx[1], t_approx[2]]"
    if old in src:
        open(pose, "w").write(src.replace(old, "Transform_good[:3, 3:] = t_approx"))

    start = time.monotonic()
    log = open(os.path.join(work, "run_system.log"), "w")
    rc = subprocess.call(["/usr/bin/python3", "run_system.py", "--config", config, "--make", "--register", "--refine",
                          "--integrate"], cwd=os.path.join(code, "reconstruction_system"), stdout=log,
                         stderr=subprocess.STDOUT)
    seconds = time.monotonic() - start
    trajectory = os.path.join(dataset, "scene", "trajectory.log")
    if rc != 0 or not os.path.exists(trajectory):
        tail = open(os.path.join(work, "run_system.log")).read().strip().splitlines()[-1:] or ["no output"]
        sys.exit(f"open3d peer: run_system.py failed (exit {rc}): {tail[0][:200]}")
    shutil.copy(trajectory, out_log)
    # Peak resident memory of the largest process it ran (joblib's workers are processes of
    # their own: their sum at any moment can be higher).
    peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
    print(json.dumps({"seconds": seconds, "frames": len(info["frames"]), "peak_memory_bytes": peak, "log": out_log}))


if __name__ == "__main__":
    main()

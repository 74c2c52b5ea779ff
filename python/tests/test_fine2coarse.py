"""The Python module against the command line on a small simulated scan (run by ctest with
PYTHONPATH at build/python and F2C_CLI naming the command line's binary)."""

import gc
import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import fine2coarse

CLI = os.environ.get("F2C_CLI", "fine2coarse")
SHARED = os.environ.get("F2C_SHARED_DATA_DIR", "")
N = 12  # frames of the simulated scan


# Under the sanitized build ctest preloads AddressSanitizer's runtime for Python; the command
# line links its own, and must not get a second.
UNDER_ASAN = "asan" in os.environ.get("LD_PRELOAD", "")


def cli(*args):
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    return subprocess.run([CLI, *map(str, args)], check=True, capture_output=True, text=True, env=env).stdout


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    """An N-frame two-room scan with exact truth, as `fine2coarse simulate` writes it."""
    path = tmp_path_factory.mktemp("scan") / "two-rooms"
    truth = fine2coarse.simulate("two-rooms", N, 0, path, correspondences=50)
    return path, truth


@pytest.fixture(scope="module")
def registered(scan):
    return fine2coarse.register(scan[0], window_frames=4)


def read_tum(path):
    rows = np.loadtxt(path, comments="#")
    return rows[:, 0], rows[:, 1:4], rows[:, 4:8]


def rotation_from_quaternion(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_simulate_returns_the_truth_it_writes(scan):
    path, truth = scan
    assert truth.shape == (N, 4, 4)
    _, t, q = read_tum(path / "groundtruth.txt")
    np.testing.assert_allclose(truth[:, :3, 3], t, atol=1e-9)


def test_register_equals_the_command_line(scan, registered, tmp_path):
    cli("register", scan[0], "-o", tmp_path, "-q", "--no-mesh", "--no-report", "--no-cache", "--window-frames", 4)
    stamps, t, q = read_tum(tmp_path / "trajectory.txt")
    r = registered
    assert r.poses.shape == (N, 4, 4) and r.poses.dtype == np.float64
    np.testing.assert_allclose(r.timestamps, stamps, atol=1e-6)
    # The file holds 9 decimals: equal to its rounding.
    np.testing.assert_allclose(r.poses[:, :3, 3], t, atol=1e-9)
    for k in range(len(q)):
        np.testing.assert_allclose(r.poses[k, :3, :3], rotation_from_quaternion(q[k]), atol=4e-9)
    np.testing.assert_array_equal(r.poses[:, 3, :], np.tile([0, 0, 0, 1], (N, 1)))
    # And what save() writes is the command line's file, byte for byte.
    names = r.save(tmp_path / "saved", report=False)
    assert "trajectory.txt" in names
    assert (tmp_path / "saved" / "trajectory.txt").read_bytes() == (tmp_path / "trajectory.txt").read_bytes()


def test_the_result_describes_the_run(registered):
    r = registered
    assert r.t0.shape == (N, 4, 4)
    assert len(r.frame_ids) == N and all(isinstance(i, str) for i in r.frame_ids)
    assert len(r.odometry) == N - 1
    assert {"frame", "reference", "method", "inliers", "fitness"} <= set(r.odometry[0])
    assert r.odometry[0]["method"] in ("SIFT", "track", "ICP", "motion prior", "sift", "icp")
    stats = r.stats
    assert stats["frames"] == N
    assert stats["stages"]["refine"]["iterations"]
    assert r.mesh is None  # not asked for
    assert f"{N} frames, refined" in repr(r)


def test_refined_poses_are_better_than_t0(scan, registered):
    truth_file = scan[0] / "groundtruth.txt"
    refined = fine2coarse.evaluate(registered.poses, truth_file, timestamps=registered.timestamps)
    t0 = fine2coarse.evaluate(registered.t0, truth_file, timestamps=registered.timestamps)
    assert refined["ate_m"]["rmse"] < t0["ate_m"]["rmse"]


def test_evaluate_equals_the_command_line(scan, registered, tmp_path):
    registered.save(tmp_path, report=False)
    expected = json.loads(cli("evaluate", "--json", "--estimate", tmp_path / "trajectory.txt", "--ground-truth",
                              scan[0] / "groundtruth.txt"))
    from_file = fine2coarse.evaluate(tmp_path / "trajectory.txt", scan[0] / "groundtruth.txt")
    for key in ("ate_m", "rpe_per_frame", "rpe_per_second", "rotation_drift_deg"):
        assert from_file[key] == expected[key], key
    # From arrays (the file's poses rounded to 9 decimals, the arrays not): the same to that.
    from_arrays = fine2coarse.evaluate(registered.poses, scan[0], timestamps=registered.timestamps)
    assert from_arrays["ate_m"]["rmse"] == pytest.approx(expected["ate_m"]["rmse"], abs=1e-8)


def test_evaluate_on_a_folder_adds_the_correspondence_error(scan, registered, tmp_path):
    stamps, _, _ = read_tum(scan[0] / "groundtruth.txt")
    truth = fine2coarse.evaluate(scan[1], scan[0], timestamps=stamps)
    assert truth["correspondences"]["distance_m"]["count"] > 0
    assert truth["correspondences"]["distance_m"]["rmse"] < 1e-3  # the sensor's exact depth at the truth
    registered.save(tmp_path, report=False)
    expected = json.loads(cli("evaluate", "--json", "--estimate", tmp_path / "trajectory.txt", "--ground-truth",
                              scan[0]))
    got = fine2coarse.evaluate(tmp_path / "trajectory.txt", scan[0])
    assert got["correspondences"] == expected["correspondences"]


def test_fuse_from_arrays_or_a_file(scan, tmp_path):
    path, truth = scan
    from_array = fine2coarse.fuse(path, truth, voxel_size=0.05, out=tmp_path / "mesh.ply")
    from_file = fine2coarse.fuse(path, path / "groundtruth.txt", voxel_size=0.05)
    assert from_array["vertices"].shape[0] > 100
    # The file's poses are rounded to 9 decimals: the same surface, vertex for vertex nearly.
    assert from_array["vertices"].shape == from_file["vertices"].shape
    np.testing.assert_allclose(from_array["vertices"], from_file["vertices"], atol=1e-5)
    assert (tmp_path / "mesh.ply").stat().st_size > 1000
    with pytest.raises(fine2coarse.InputError, match=f"poses: {N - 1} poses for {N} frames"):
        fine2coarse.fuse(path, truth[:-1])
    with pytest.raises(fine2coarse.InputError, match="--voxel-size"):
        fine2coarse.fuse(path, truth, voxel_size=-1.0)


def test_mesh_as_arrays(scan):
    r = fine2coarse.register(scan[0], window_frames=4, features=False, mesh=True, voxel_size=0.05)
    m = r.mesh
    assert m["vertices"].shape[1] == 3 and m["vertices"].shape[0] > 100
    assert m["triangles"].dtype == np.int32 and m["triangles"].max() < m["vertices"].shape[0]
    assert m["colors"].dtype == np.uint8 and m["colors"].shape == m["vertices"].shape
    # The simulated rooms lie within a few metres of the origin.
    assert np.abs(m["vertices"]).max() < 20


def test_progress_reaches_every_stage_and_the_gil_is_released(scan):
    heard = []
    ticks = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    try:
        fine2coarse.register(scan[0], window_frames=4, progress=lambda stage, done, total: heard.append(stage))
    finally:
        stop.set()
        thread.join()
    assert "odometry" in heard and "refine" in heard
    assert ticks[0] > 50  # the other thread ran while register worked


def test_quiet_by_default(tmp_path, capfd):
    fine2coarse.simulate("two-rooms", 5, 0, tmp_path / "short", correspondences=0)
    capfd.readouterr()
    fine2coarse.register(tmp_path / "short", stop_after="odometry")
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    # quiet=False logs as the command line does (and a quiet call before left the log level as it was).
    fine2coarse.register(tmp_path / "short", stop_after="odometry", quiet=False)
    out, err = capfd.readouterr()
    assert "odometry: 4 frames aligned" in out + err


def test_an_exception_in_the_progress_callback_reaches_the_caller(scan):
    def fail(stage, done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        fine2coarse.register(scan[0], window_frames=4, stop_after="odometry", progress=fail)


def test_read_sequence_gives_the_frames_and_truth(scan):
    seq = fine2coarse.read_sequence(scan[0])
    assert len(seq) == N and seq.layout == "tum"
    color, depth = seq[0]
    assert color.shape == (480, 640, 3) and color.dtype == np.uint8
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    assert 0.3 < np.median(depth[depth > 0]) < 10  # metres
    np.testing.assert_allclose(seq.ground_truth, scan[1], atol=4e-9)  # the file's 9 decimals
    assert seq.intrinsics["fx"] == 525.0
    with pytest.raises(IndexError):
        seq[N]
    assert seq[-1][1].shape == (480, 640)


def test_register_frames_equals_register(scan, registered):
    seq = fine2coarse.read_sequence(scan[0])
    frames = [seq[i] for i in range(len(seq))]
    k = seq.intrinsics
    r = fine2coarse.register_frames([c for c, _ in frames], [d for _, d in frames], (k["fx"], k["fy"], k["cx"], k["cy"]),
                                    timestamps=seq.timestamps, window_frames=4)
    np.testing.assert_array_equal(r.poses, registered.poses)
    # Depth as millimetres in uint16 is the same scan (whole millimetres: 0.2 mm steps lost).
    mm = [np.round(d * 1000).astype(np.uint16) for _, d in frames]
    r_mm = fine2coarse.register_frames(np.stack([c for c, _ in frames]), mm, k, timestamps=seq.timestamps,
                                       window_frames=4, stop_after="odometry")
    assert r_mm.poses.shape == (N, 4, 4)


def test_register_frames_refuses_what_it_cannot_read(scan):
    seq = fine2coarse.read_sequence(scan[0])
    c, d = seq[0]
    k = (525.0, 525.0, 319.5, 239.5)
    cases = [
        (([c, c], [d]), {}, "depths: 1 depth images for 2 colour images"),
        (([c], [d]), {}, "colors: registration needs at least 2 frames"),
        (([c, c[:, :, 0]], [d, d]), {}, "colors: frame 1: shape 480 x 640 (wanted 480 x 640 x 3)"),
        (([c, c], [d, d.astype(np.float64)]), {}, "depths: frame 1: dtype float64 (wanted uint16)"),
        (([c, c], [d, d[:100]]), {}, "depths: frame 1: shape 100 x 640 (wanted 480 x 640)"),
        (([c, c], [d, d]), {"timestamps": [1.0, 1.0]}, "timestamps: must be finite and increasing (frame 1)"),
        (([c, c], [d, d]), {"depth_scale": 0.0}, "depth_scale: must be a positive number of metres per unit"),
    ]
    for (colors, depths), extra, message in cases:
        with pytest.raises(fine2coarse.InputError) as e:
            fine2coarse.register_frames(colors, depths, k, **extra)
        assert message in str(e.value)
    with pytest.raises(fine2coarse.InputError, match="intrinsics: must be"):
        fine2coarse.register_frames([c, c], [d, d], (1.0, 2.0))


BAD_REGISTER = [
    ({"colour": 3}, "colour: unknown option"),
    ({"window_frames": 1}, "--window-frames: must be >= 2, got 1"),
    ({"window_frames": "eight"}, "--window-frames: must be a whole number, got 'eight'"),
    ({"window_frames": 2.5}, "--window-frames: must be a whole number, got 2.5"),
    ({"window_frames": 2**70}, "--window-frames: must be a whole number within the option's type"),
    ({"structure": 1}, "--structure: must be True or False, got 1"),
    ({"preset": "slow"}, "--preset: unknown value 'slow' (default, fast, paper)"),
    ({"stop_after": "mesh"}, "--stop-after: must be 'odometry' or 'refine'"),
    ({"threads": -1}, "--threads: must be in [0, 1024], got -1"),
    ({"mesh": "yes"}, "--mesh: must be True or False"),
    ({"loss": "square"}, "--loss: unknown value 'square'"),
    ({"loss_scale": float("nan")}, "--loss-scale: must be > 0, got nan"),
    ({"every": 0}, "--every: must be >= 1, got 0"),
    ({"seed": -1}, "--seed: must be a whole number >= 0, got -1"),
    ({"window_frames": None}, "--window-frames: must not be None"),
    ({"features": False, "initial_trajectory": __file__}, "--initial-trajectory: only the refinement starts from it"),
]


@pytest.mark.parametrize("options,message", BAD_REGISTER)
def test_bad_options_raise_input_error_with_the_command_lines_message(scan, options, message):
    with pytest.raises(fine2coarse.InputError) as e:
        fine2coarse.register(scan[0], **options)
    assert message in str(e.value)
    assert isinstance(e.value, ValueError)


def test_bad_calls(scan, tmp_path):
    with pytest.raises(FileNotFoundError):
        fine2coarse.register(tmp_path / "missing")
    with pytest.raises(TypeError):
        fine2coarse.register(42)
    with pytest.raises(fine2coarse.InputError, match="estimate: must have shape N x 4 x 4, got 3 x 3"):
        fine2coarse.evaluate(np.eye(3), scan[0])
    with pytest.raises(fine2coarse.InputError, match="estimate: must be an array of N x 4 x 4 numbers"):
        fine2coarse.evaluate([["a"]], scan[0])
    poses = np.tile(np.eye(4), (N, 1, 1))
    poses[3, 0, 3] = np.nan
    with pytest.raises(fine2coarse.InputError, match="estimate:4"):
        fine2coarse.evaluate(poses, scan[0])
    with pytest.raises(fine2coarse.InputError, match=f"estimate: 2 time stamps for {N} poses"):
        fine2coarse.evaluate(np.tile(np.eye(4), (N, 1, 1)), scan[0], timestamps=[0.0, 1.0])
    with pytest.raises(fine2coarse.InputError, match="--scene"):
        fine2coarse.simulate("castle", 10, 0, tmp_path / "castle")
    with pytest.raises(fine2coarse.InputError, match="--max-time-difference"):
        fine2coarse.evaluate(np.tile(np.eye(4), (N, 1, 1)), scan[0], max_time_difference=-1)
    # A non-contiguous array, or one of another dtype, is read as it is.
    stamps, _, _ = read_tum(scan[0] / "groundtruth.txt")
    wide = np.zeros((N, 4, 8))
    wide[:, :, ::2] = scan[1]
    expected = fine2coarse.evaluate(scan[1], scan[0], timestamps=stamps)
    assert fine2coarse.evaluate(wide[:, :, ::2], scan[0], timestamps=stamps) == expected
    assert fine2coarse.evaluate(scan[1].astype(np.float32), scan[0], timestamps=stamps)["ate_m"]["rmse"] < 1e-6
    assert expected["ate_m"]["rmse"] < 1e-9  # the truth against itself


def test_repeated_calls_leave_no_references_behind(scan, registered):
    """Under any build: the arguments' reference counts and the number of live Python objects
    do not grow over 100 calls of each entry point (bad calls included)."""
    truth = scan[0] / "groundtruth.txt"
    poses, stamps = registered.poses, registered.timestamps

    def work():
        for _ in range(100):
            fine2coarse.evaluate(poses, truth, timestamps=stamps)
            _ = registered.poses, registered.stats, registered.odometry, registered.frame_ids
            for bad in ({"colour": 1}, {"window_frames": "x"}):
                try:
                    fine2coarse.register(scan[0], **bad)
                except fine2coarse.InputError:
                    pass
            try:
                fine2coarse.evaluate(poses[:, :3, :3], truth)
            except fine2coarse.InputError:
                pass
        gc.collect()

    work()
    refs = (sys.getrefcount(poses), sys.getrefcount(stamps), sys.getrefcount(registered))
    objects = len(gc.get_objects())
    work()
    assert (sys.getrefcount(poses), sys.getrefcount(stamps), sys.getrefcount(registered)) == refs
    assert len(gc.get_objects()) - objects < 50


def rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


@pytest.mark.skipif(UNDER_ASAN, reason="AddressSanitizer's quarantine holds freed memory: RSS measures no leak there "
                    "(bash scripts/test.sh --release runs it)")
def test_repeated_calls_do_not_leak(scan, registered):
    truth = scan[0] / "groundtruth.txt"

    def work():
        for _ in range(100):
            fine2coarse.evaluate(registered.poses, truth, timestamps=registered.timestamps)
            assert registered.poses.shape == (N, 4, 4)
            _ = registered.stats
            try:
                fine2coarse.register(scan[0], colour=1)
            except fine2coarse.InputError:
                pass
        gc.collect()

    work()  # the allocator's pools fill once
    before = rss_kib()
    work()
    assert rss_kib() - before < 4096, "RSS grew over 100 calls"


@pytest.mark.skipif(not os.path.isdir(os.path.join(SHARED, "tum_fr1_xyz_15hz")), reason="../shared/data absent")
def test_real_data_first_frames():
    r = fine2coarse.register(os.path.join(SHARED, "tum_fr1_xyz_15hz"), intrinsics="tum-fr1", last=29,
                             stop_after="odometry")
    assert r.poses.shape == (30, 4, 4)
    e = fine2coarse.evaluate(r.poses, os.path.join(SHARED, "tum_fr1_xyz_15hz"), timestamps=r.timestamps)
    assert e["ate_m"]["rmse"] < 0.05

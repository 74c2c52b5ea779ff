#!/usr/bin/env bash
# Keyframe odometry (issue 13): T0's accuracy and cost with keyframes (the default), with
# consecutive pairs on every frame (--keyframes off), and with consecutive pairs on every
# second frame (--every 2, what the 15 Hz sets hold), on simulated 30 Hz walks; T0 and the
# refined result on the real sequences.
#
#   bash bench/keyframe_bench.sh [build dir] [work dir] [seeds]
#
# "shared frames": every second frame of the full-rate runs, evaluated on its own (so it is
# compared with --every 2 on the same frames). Each register runs fresh (--no-cache) with
# T0 and the features (--stop-after odometry) for the timing column; the real sequences
# also run the refinement.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
seeds="${3:-0 1 2}"
mkdir -p "$work"
data="$(pwd)/../shared/data"
results="$work/results.txt"
: > "$results"

evaluate() {  # trajectory ground_truth_dir out.json
  "$bin" evaluate --json --estimate "$1" --ground-truth "$2" > "$3"
}
# Every second line of a TUM trajectory (frames 0, 2, 4, ...).
even_frames() { grep -v '^#' "$1" | awk 'NR % 2 == 1'; }

for scene in two-rooms apartment; do
  for seed in $seeds; do
    sim="$work/sim-$scene-$seed"
    [ -f "$sim/groundtruth.txt" ] || "$bin" simulate --scene "$scene" --frames 900 --seed "$seed" -o "$sim" -q > /dev/null
    for mode in default off every2; do
      out="$work/$scene-$seed-$mode"
      case $mode in
        default) args=() ;;
        off) args=(--keyframes off) ;;
        every2) args=(--keyframes off --every 2) ;;
      esac
      "$bin" register "$sim" -o "$out" -q --no-cache --stop-after odometry "${args[@]}" > "$out.log" 2>&1
      evaluate "$out/trajectory.txt" "$sim" "$out/eval.json"
      even_frames "$out/trajectory.txt" > "$out/even.txt"
      evaluate "$out/even.txt" "$sim" "$out/eval_even.json"
      echo "sim $scene $seed $mode $out" >> "$results"
    done
  done
done

for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skip $seq: $data/$seq absent" >&2; continue; }
  k=(); [ -f "$data/$seq/rgb.txt" ] && k=(--intrinsics tum-fr1)
  for mode in default off; do
    out="$work/$seq-$mode"
    args=(); [ "$mode" = off ] && args=(--keyframes off)
    "$bin" register "$data/$seq" -o "$out" -q --no-cache --no-mesh "${k[@]}" "${args[@]}" > "$out.log" 2>&1
    evaluate "$out/trajectory.txt" "$data/$seq" "$out/eval.json"
    evaluate "$out/trajectory_t0.txt" "$data/$seq" "$out/eval_t0.json"
    echo "real $seq 0 $mode $out" >> "$results"
  done
done

/usr/bin/python3 - "$results" <<'PY'
import json, sys
from collections import defaultdict
rows = defaultdict(dict)
real = []
for line in open(sys.argv[1]):
    kind, scene, seed, mode, out = line.split()
    run = json.load(open(out + "/run.json"))
    o = run["stages"]["odometry"]
    st = run["statistics"]["odometry"]
    if kind == "sim":
        ev, even = json.load(open(out + "/eval.json")), json.load(open(out + "/eval_even.json"))
        corr = ev["correspondences"]["distance_m"]["rmse"] if "correspondences" in ev else float("nan")
        rows[(scene, seed)][mode] = dict(ate=ev["ate_m"]["rmse"], even=even["ate_m"]["rmse"], corr=corr,
                                         sift=o["sift_per_frame"], ms=1000 * run["total_wall_s"] / run["frames"],
                                         kf=st.get("keyframes", 0), icp=st["icp"])
    else:
        ev, ev0 = json.load(open(out + "/eval.json")), json.load(open(out + "/eval_t0.json"))
        real.append((scene, mode, ev0["ate_m"]["rmse"], ev["ate_m"]["rmse"], o["sift_per_frame"],
                     1000 * run["total_wall_s"] / run["frames"], st.get("keyframes", 0)))
print("| scene | seed | T0 ATE all frames: keyframes / off (m) | shared frames: keyframes / off / --every 2 (m) | corr. RMSE: keyframes / off / every 2 (m) | SIFT per input frame: keyframes / off | keyframes | ms per input frame (T0 + features): keyframes / off / every 2 |")
print("|---|---|---|---|---|---|---|---|")
sums = defaultdict(float)
for (scene, seed), m in rows.items():
    d, f, e = m["default"], m["off"], m["every2"]
    # --every 2 registers half the frames: its time per *input* frame is over all 900.
    e_ms = e["ms"] / 2
    print(f"| {scene} | {seed} | {d['ate']:.3f} / {f['ate']:.3f} | {d['even']:.3f} / {f['even']:.3f} / {e['even']:.3f} | "
          f"{d['corr']:.3f} / {f['corr']:.3f} / {e['corr']:.3f} | {d['sift']:.2f} / {f['sift']:.2f} | {d['kf']} | "
          f"{d['ms']:.1f} / {f['ms']:.1f} / {e_ms:.1f} |")
    for k, v in (("d_ate", d["ate"]), ("f_ate", f["ate"]), ("d_even", d["even"]), ("f_even", f["even"]), ("e_even", e["even"]),
                 ("d_ms", d["ms"]), ("f_ms", f["ms"]), ("n", 1)):
        sums[k] += v
n = sums["n"]
if n:
    print(f"| **mean** | | {sums['d_ate']/n:.3f} / {sums['f_ate']/n:.3f} | {sums['d_even']/n:.3f} / {sums['f_even']/n:.3f} / {sums['e_even']/n:.3f} | | | | "
          f"{sums['d_ms']/n:.1f} / {sums['f_ms']/n:.1f} (x{sums['f_ms']/sums['d_ms']:.2f}) |")
if real:
    print()
    print("| sequence | mode | T0 ATE (m) | refined ATE (m) | SIFT per frame | ms per frame (all stages) | keyframes |")
    print("|---|---|---|---|---|---|---|")
    for scene, mode, t0, ref, sift, ms, kf in real:
        print(f"| {scene} | {mode} | {t0:.4f} | {ref:.4f} | {sift:.2f} | {ms:.1f} | {kf} |")
PY

#!/usr/bin/env bash
# How T0's error grows with path length on simulated multi-room scans: simulate each scene
# once (N frames at 30 Hz, seed 0, default sensor model), register prefixes of it, and
# evaluate each against the exact ground truth.
#   bash bench/sim_odometry_bench.sh [build dir] [frames]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/apps/fine2coarse"
frames="${2:-900}"
tmp=$(mktemp -d)
printf '| scene | frames | path (m) | T0 ATE RMSE (m) | RPE/frame (m, deg) | SIFT/ICP/prior |\n|---|---|---|---|---|---|\n'
for scene in two-rooms apartment; do
  "$bin" simulate --scene "$scene" --frames "$frames" --seed 0 -o "$tmp/$scene" -q >/dev/null
  for n in 150 300 600 "$frames"; do
    [ "$n" -le "$frames" ] || continue
    out="$tmp/$scene-$n"
    "$bin" register "$tmp/$scene" --last $((n - 1)) -o "$out" -q --no-cache >/dev/null
    "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$tmp/$scene" > "$out/eval.json"
    /usr/bin/python3 - "$scene" "$n" "$out" "$tmp/$scene/groundtruth.txt" <<'PY'
import json, math, sys
scene, n, out, gt = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
ev = json.load(open(out + "/eval.json")); st = json.load(open(out + "/run.json"))["statistics"]["odometry"]
pts = [list(map(float, l.split()[1:4])) for l in open(gt) if not l.startswith("#")][:n]
path = sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
print(f"| {scene} | {n} | {path:.1f} | {ev['ate_m']['rmse']:.3f} | {ev['rpe_per_frame']['translation_m']['rmse']:.4f}, "
      f"{ev['rpe_per_frame']['rotation_deg']['rmse']:.3f} | {st['sift']}/{st['icp']}/{st['motion_prior']} |")
PY
  done
done
rm -rf "$tmp"

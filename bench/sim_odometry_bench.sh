#!/usr/bin/env bash
# How T0's error grows with path length on simulated multi-room scans: simulate each scene
# once per seed (N frames at 30 Hz, default sensor model; the seed changes furniture,
# posters, the walk and the noise), register prefixes of it, and evaluate each against the
# exact ground truth (ATE, RPE, and the RMSE of the scan's ground-truth correspondences
# between the registered frames). One row per scene and prefix, over all seeds.
#   bash bench/sim_odometry_bench.sh [build dir] [frames] [seeds]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/apps/fine2coarse"
frames="${2:-900}"
seeds="${3:-0 1 2}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in two-rooms apartment; do
  for seed in $seeds; do
    "$bin" simulate --scene "$scene" --frames "$frames" --seed "$seed" -o "$tmp/$scene-$seed" -q >/dev/null
    for n in 150 300 600 "$frames"; do
      [ "$n" -le "$frames" ] || continue
      out="$tmp/$scene-$seed-$n"
      "$bin" register "$tmp/$scene-$seed" --last $((n - 1)) -o "$out" -q --no-cache --no-mesh >/dev/null
      "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$tmp/$scene-$seed" > "$out/eval.json"
      echo "$scene $seed $n $out $tmp/$scene-$seed/groundtruth.txt" >> "$tmp/runs.txt"
    done
  done
done
/usr/bin/python3 - "$tmp/runs.txt" <<'PY'
import json, math, sys
from collections import defaultdict
rows = defaultdict(list)
for line in open(sys.argv[1]):
    scene, seed, n, out, gt = line.split()
    n = int(n)
    ev = json.load(open(out + "/eval.json"))
    st = json.load(open(out + "/run.json"))["statistics"]["odometry"]
    pts = [list(map(float, l.split()[1:4])) for l in open(gt) if not l.startswith("#")][:n]
    path = sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
    corr = ev["correspondences"]["distance_m"]["rmse"] if "correspondences" in ev else float("nan")
    rows[(scene, n)].append((seed, path, ev["ate_m"]["rmse"], ev["rpe_per_frame"]["translation_m"]["rmse"],
                             ev["rpe_per_frame"]["rotation_deg"]["rmse"], st["sift"], st["icp"], st["motion_prior"], corr))
print("| scene | frames | path (m, mean) | T0 ATE RMSE (m) per seed | mean ATE (m) | correspondence RMSE (m, mean) | RPE/frame (m, deg; mean) | SIFT/ICP/prior (all seeds) |")
print("|---|---|---|---|---|---|---|---|")
for (scene, n), r in rows.items():
    mean = lambda i: sum(x[i] for x in r) / len(r)
    total = lambda i: sum(x[i] for x in r)
    per_seed = " / ".join(f"{x[2]:.3f}" for x in r)
    print(f"| {scene} | {n} | {mean(1):.1f} | {per_seed} | {mean(2):.3f} | {mean(8):.3f} | {mean(3):.4f}, {mean(4):.3f} | "
          f"{total(5)}/{total(6)}/{total(7)} |")
PY

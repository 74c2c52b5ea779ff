#!/usr/bin/env bash
# Accuracy and speed of T0 (SIFT + 3D RANSAC odometry) on the real sequences with ground
# truth. Prints one markdown table; each run is fresh (--no-cache).
#   bash bench/odometry_bench.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/apps/fine2coarse"
data=../shared/data
tmp=$(mktemp -d)
printf '| sequence | frames | ATE RMSE (m) | RPE/frame (m, deg) | RPE/s (m, deg) | decode | SIFT | matching | RANSAC | ICP | wall per frame | frames/s | SIFT/ICP/prior |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skip $seq: $data/$seq absent" >&2; continue; }
  k=(); [ -f "$data/$seq/rgb.txt" ] && k=(--intrinsics tum-fr1)
  "$bin" register "$data/$seq" -o "$tmp/$seq" "${k[@]}" --no-cache --no-mesh -q >/dev/null
  "$bin" evaluate --json --estimate "$tmp/$seq/trajectory.txt" --ground-truth "$data/$seq" > "$tmp/$seq/eval.json"
  /usr/bin/python3 - "$seq" "$tmp/$seq" <<'PY'
import json, sys
seq, d = sys.argv[1], sys.argv[2]
run = json.load(open(d + "/run.json")); ev = json.load(open(d + "/eval.json"))
o = run["stages"]["odometry"]; ms = o["cpu_ms_per_frame"]; st = run["statistics"]["odometry"]
n = run["frames"]; wall = run["total_wall_s"]
print(f"| {seq} | {n} | {ev['ate_m']['rmse']:.4f} | {ev['rpe_per_frame']['translation_m']['rmse']:.4f}, "
      f"{ev['rpe_per_frame']['rotation_deg']['rmse']:.3f} | {ev['rpe_per_second']['translation_m']['rmse']:.4f}, "
      f"{ev['rpe_per_second']['rotation_deg']['rmse']:.3f} | {ms['decode']:.1f} ms | {ms['sift']:.1f} ms | "
      f"{ms['matching']:.1f} ms | {ms['ransac']:.1f} ms | {ms['icp']:.1f} ms | {1000*wall/n:.1f} ms | {n/wall:.1f} | "
      f"{st['sift']}/{st['icp']}/{st['motion_prior']} |")
PY
done
rm -rf "$tmp"

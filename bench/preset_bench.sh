#!/usr/bin/env bash
# The presets' table (src/f2c/pipeline/preset.h): each dataset registered end to end with no
# cache (odometry, features, refinement, mesh; no report) under --preset default, fast and
# paper, one after the other on the same machine: the result's ATE and the frames per second
# of the whole run, with each stage's milliseconds per frame.
#
#   bash bench/preset_bench.sh [build dir] [work dir]
#
# Real data: ../shared/data/tum_fr1_xyz_15hz, tum_fr1_desk_15hz, 7scenes_redkitchen_15hz
# (skipped where absent). Simulated: the object scene (600 frames, seed 0) and the two-rooms
# and apartment walks (900 frames, seed 0). The work dir keeps the simulations.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"

row() {  # label dir extra args...
  local label="$1" dir="$2"
  shift 2
  for preset in default fast paper; do
    local out="$work/$label-$preset"
    rm -rf "$out"
    "$bin" register "$dir" -o "$out" -q --no-cache --no-report --preset "$preset" "$@" > "$out.log" 2>&1
    local ate
    ate=$("$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$dir" |
      /usr/bin/python3 -c 'import json, sys; print("%.4f" % json.load(sys.stdin)["ate_m"]["rmse"])')
    /usr/bin/python3 - "$out/run.json" "$label" "$preset" "$ate" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s, n = r["stages"], r["frames"]
ms = lambda x: "%.1f" % x
print("| %s | %s | %s | %.1f | %s | %s | %s |" % (
    sys.argv[2], sys.argv[3], sys.argv[4], n / r["total_wall_s"],
    ms(1000 * s["odometry"]["wall_s"] / n), ms(s["refine"]["ms_per_frame"]), ms(s["fusion"]["ms_per_frame"])))
PY
  done
}

echo "| dataset | preset | ATE (m) | frames/s end to end | odometry + features ms/frame | refinement ms/frame | mesh ms/frame |"
echo "|---|---|---|---|---|---|---|"
for seq in tum_fr1_xyz_15hz tum_fr1_desk_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent" >&2; continue; }
  extra=()
  [[ "$seq" == tum_* ]] && extra=(--intrinsics tum-fr1)
  row "$seq" "$data/$seq" "${extra[@]}"
done
for scene in object two-rooms apartment; do
  frames=900
  [ "$scene" = object ] && frames=600
  [ -f "$work/sim-$scene-0/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames "$frames" --seed 0 -q -o "$work/sim-$scene-0" > /dev/null
  row "$scene-0" "$work/sim-$scene-0"
done

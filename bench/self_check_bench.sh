#!/usr/bin/env bash
# The self-check's table (refine/self_check.h): each dataset registered with the check (the
# default) and with --no-self-check, T0's and the result's ATE and ground-truth
# correspondence RMSE, the iterations the check undid, and the refinement's ms per frame.
#
#   bash bench/self_check_bench.sh [build dir] [work dir]
#
# Real data: ../shared/data/tum_fr1_xyz_15hz, tum_fr1_desk_15hz, 7scenes_redkitchen_15hz
# (skipped where absent). Simulated: the object scene (600 frames, seeds 0, 1, 2) and the
# two-rooms and apartment walks (900 frames, seed 0). The work dir keeps the simulations.
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"

measure() {  # estimate ground_truth -> "ATE corr"
  "$bin" evaluate --json --estimate "$1" --ground-truth "$2" | /usr/bin/python3 -c '
import json, sys
e = json.load(sys.stdin)
c = e.get("correspondences", {}).get("distance_m", {}).get("rmse")
a = e["ate_m"]["rmse"]
print("%.4f %s" % (a, "-" if c is None else "%.4f" % c))'
}
printf "%-22s %-6s %8s %8s %8s %8s %7s %7s\n" dataset check "T0 ATE" "T0 corr" "ATE m" "corr m" undone "ms/fr"
row() {  # label dir extra args...
  local label="$1" dir="$2"
  shift 2
  for check in on off; do
    local out="$work/$label-$check" args=()
    [ "$check" = off ] && args=(--no-self-check)
    "$bin" register "$dir" -o "$out" -q --no-mesh --no-report "$@" "${args[@]}" > "$out.log" 2>&1
    read -r t0_ate t0_corr <<< "$(measure "$out/trajectory_t0.txt" "$dir")"
    read -r ate corr <<< "$(measure "$out/trajectory.txt" "$dir")"
    read -r undone ms <<< "$(/usr/bin/python3 -c '
import json, sys
r = json.load(open(sys.argv[1]))["stages"]["refine"]
print(r["self_check_undone_iterations"], "%.1f" % r["ms_per_frame"])' "$out/run.json")"
    printf "%-22s %-6s %8s %8s %8s %8s %7s %7s\n" "$label" "$check" "$t0_ate" "$t0_corr" "$ate" "$corr" "$undone" "$ms"
  done
}

for seq in tum_fr1_xyz_15hz tum_fr1_desk_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent"; continue; }
  extra=()
  [[ "$seq" == tum_* ]] && extra=(--intrinsics tum-fr1)
  row "$seq" "$data/$seq" "${extra[@]}"
done
for seed in 0 1 2; do
  [ -f "$work/sim-object-$seed/rgb.txt" ] || "$bin" simulate --scene object --frames 600 --seed "$seed" -q -o "$work/sim-object-$seed" > /dev/null
  row "object-$seed" "$work/sim-object-$seed"
done
for scene in two-rooms apartment; do
  [ -f "$work/sim-$scene-0/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames 900 --seed 0 -q -o "$work/sim-$scene-0" > /dev/null
  row "$scene-0" "$work/sim-$scene-0"
done

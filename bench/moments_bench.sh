#!/usr/bin/env bash
# Colour and depth taken at different moments (RgbdFrame::color_time): each dataset registered
# with frames stamped by their colour image (the two taken as one moment: the TUM tools'
# convention), by their depth image, and by their depth image with what colour measured
# referred to the depth's moment (--sync-color on, the default). T0's and the result's ATE,
# and the whole run's seconds.
#
#   bash bench/moments_bench.sh [build dir] [work dir]
#
# Real data: ../shared/data/tum_fr1_xyz_15hz, tum_fr1_desk_15hz, 7scenes_redkitchen_15hz
# (skipped where absent; 7-Scenes has no per-image stamps, so its three rows must agree).
# Simulated: the object scene (300 frames, seed 0), whose colour and depth share their
# moments (its rows must agree too).
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"

ate() { "$bin" evaluate --json --estimate "$1" --ground-truth "$2" | /usr/bin/python3 -c '
import json, sys
print("%.4f" % json.load(sys.stdin)["ate_m"]["rmse"])'; }
printf "%-24s %-6s %-5s %8s %8s %7s\n" dataset stamp sync "T0 ATE" "ATE m" "run s"
row() {  # label dir extra args...
  local label="$1" dir="$2"
  shift 2
  for config in "color off" "depth off" "depth on"; do
    read -r stamp sync <<< "$config"
    local out="$work/$label-$stamp-$sync"
    rm -rf "$out"
    "$bin" register "$dir" -o "$out" -q --no-mesh --no-report --stamp "$stamp" --sync-color "$sync" "$@" \
      > "$out.log" 2>&1
    local seconds
    seconds="$(/usr/bin/python3 -c 'import json, sys; print("%.1f" % json.load(open(sys.argv[1]))["total_wall_s"])' \
      "$out/run.json")"
    printf "%-24s %-6s %-5s %8s %8s %7s\n" "$label" "$stamp" "$sync" "$(ate "$out/trajectory_t0.txt" "$dir")" \
      "$(ate "$out/trajectory.txt" "$dir")" "$seconds"
  done
}

for seq in tum_fr1_xyz_15hz tum_fr1_desk_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent"; continue; }
  extra=()
  [[ "$seq" == tum_* ]] && extra=(--intrinsics tum-fr1)
  row "$seq" "$data/$seq" "${extra[@]}"
done
[ -f "$work/sim-object-0/rgb.txt" ] || "$bin" simulate --scene object --frames 300 --seed 0 -q -o "$work/sim-object-0" > /dev/null
row "object-0 (300 frames)" "$work/sim-object-0"
# Simulated walks whose colour is taken up to 15 ms before or after depth (--color-offset 15):
# depth stamps, without and with the colour referred to the depth's moment.
printf "\n%-24s %-5s %8s %8s\n" "walk (150 frames)" sync "T0 ATE" "ATE m"
for scene in apartment two-rooms; do
  for seed in 0 1 2; do
    sim="$work/sim-$scene-$seed-offset"
    [ -f "$sim/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames 150 --seed "$seed" --color-offset 15 -q \
      -o "$sim" > /dev/null
    for sync in off on; do
      out="$work/$scene-$seed-offset-$sync"
      rm -rf "$out"
      "$bin" register "$sim" -o "$out" -q --no-mesh --no-report --sync-color "$sync" > "$out.log" 2>&1
      printf "%-24s %-5s %8s %8s\n" "$scene-$seed" "$sync" "$(ate "$out/trajectory_t0.txt" "$sim")" \
        "$(ate "$out/trajectory.txt" "$sim")"
    done
  done
done

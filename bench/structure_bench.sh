#!/usr/bin/env bash
# The structural model's table (issue 9): the paper's four variants (fine-to-coarse on/off x
# structure on/off) on the real sequences and on simulated walks, with ATE, the
# ground-truth correspondence RMSE, rotation drift (worst, RMS and 99th percentile over frame
# pairs >= 5 s apart; and the worst once each pose's rotation error is averaged over 1 s,
# which tells drift from single frames' jitter) and the refinement's time.
#
#   bash bench/structure_bench.sh [build dir] [work dir]
#
# Real data: ../shared/data/tum_fr1_xyz_15hz and 7scenes_redkitchen_15hz (skipped if absent).
# Simulated: two-rooms, apartment (trapezoid living room, side walls 14 deg off square) and
# apartment-square (6 deg off), 900 frames, seeds 0, 1, 2. The work dir keeps simulations and
# caches between runs (default: a fresh temporary one); a first register run per dataset
# fills the caches so that each row times the refinement alone.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
[ -x "$bin" ] || { echo "error: $bin not found: run bash scripts/build.sh first" >&2; exit 1; }
cp "$bin" "$work/fine2coarse.bin" && bin="$work/fine2coarse.bin"  # a rebuild meanwhile cannot change it
data="$(pwd)/../shared/data"

variants=(
  "full|--structure"
  "no structure|--no-structure"
  "no fine-to-coarse|--structure --no-fine-to-coarse"
  "neither|--no-structure --no-fine-to-coarse"
)

printf "%-34s %-18s %8s %8s %8s %8s %8s %8s %8s\n" dataset variant "ATE m" "corr m" "drift^" "driftRMS" "ms/fr" "drift99" "drift1s^"
row() {  # dataset_label dataset_dir out_dir variant_name args...
  local label="$1" dir="$2" out="$3" name="$4"
  shift 4
  "$bin" register "$dir" -o "$out" -q --no-mesh "$@" > "$out.log" 2>&1
  "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$dir" > "$out/eval.json"
  /usr/bin/python3 - "$out" "$label" "$name" <<'PY'
import json, sys
out, label, name = sys.argv[1:]
e = json.load(open(out + "/eval.json"))
r = json.load(open(out + "/run.json"))["stages"]["refine"]
corr = e.get("correspondences", {}).get("distance_m", {}).get("rmse")
d = e["rotation_drift_deg"]
print(f"{label:34s} {name:18s} {e['ate_m']['rmse']:8.4f} {corr if corr is not None else float('nan'):8.4f} "
      f"{d['max']:8.2f} {d['rmse']:8.3f} {r['ms_per_frame']:8.1f} {e['rotation_drift_p99_deg']:8.2f} "
      f"{e['rotation_drift_smoothed_deg']['max']:8.2f}", flush=True)
PY
}
t0_row() {  # dataset_label dataset_dir out_dir
  "$bin" evaluate --json --estimate "$3/trajectory_t0.txt" --ground-truth "$2" > "$3/eval_t0.json"
  /usr/bin/python3 - "$3" "$1" <<'PY'
import json, sys
out, label = sys.argv[1:]
e = json.load(open(out + "/eval_t0.json"))
corr = e.get("correspondences", {}).get("distance_m", {}).get("rmse")
d = e["rotation_drift_deg"]
print(f"{label:34s} {'T0':18s} {e['ate_m']['rmse']:8.4f} {corr if corr is not None else float('nan'):8.4f} "
      f"{d['max']:8.2f} {d['rmse']:8.3f} {'':>8s} {e['rotation_drift_p99_deg']:8.2f} "
      f"{e['rotation_drift_smoothed_deg']['max']:8.2f}", flush=True)
PY
}

for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent"; continue; }
  extra=()
  [ "$seq" = tum_fr1_xyz_15hz ] && extra=(--intrinsics tum-fr1)
  out="$work/real-$seq"
  "$bin" register "$data/$seq" -o "$out" -q "${extra[@]}" > /dev/null 2>&1  # caches
  t0_row "$seq" "$data/$seq" "$out"
  for v in "${variants[@]}"; do
    IFS='|' read -r name args <<< "$v"
    # shellcheck disable=SC2086
    row "$seq" "$data/$seq" "$out" "$name" "${extra[@]}" $args
  done
done

for scene in two-rooms apartment apartment-square; do
  for seed in 0 1 2; do
    sim="$work/sim-$scene-$seed"
    [ -f "$sim/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames 900 --seed "$seed" -o "$sim" -q > /dev/null
    out="$work/out-$scene-$seed"
    "$bin" register "$sim" -o "$out" -q --polish-iterations 0 --extra-iterations 0 > /dev/null 2>&1  # caches
    t0_row "$scene-$seed" "$sim" "$out"
    for v in "${variants[@]}"; do
      IFS='|' read -r name args <<< "$v"
      # shellcheck disable=SC2086
      row "$scene-$seed" "$sim" "$out" "$name" $args
    done
  done
done

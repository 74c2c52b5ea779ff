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
#
# F2C_BENCH_REFINE_SEEDS: the refinement's seeds (--refine-seed; default "0") for the walks'
# rows, one row each, labelled WALK/rSEED when there are several. The refinement samples its
# correspondences, and one walk's worst drift moves by up to 0.1 deg from seed to seed
# (BENCHMARKS.md), so a mean over several says more than one run.
set -euo pipefail
cd "$(dirname "$0")/.."
read -r -a refine_seeds <<< "${F2C_BENCH_REFINE_SEEDS:-0}"
[ "${#refine_seeds[@]}" -gt 0 ] || { echo "error: F2C_BENCH_REFINE_SEEDS names no seed" >&2; exit 1; }
for r in "${refine_seeds[@]}"; do
  [[ "$r" =~ ^[0-9]+$ ]] || { echo "error: F2C_BENCH_REFINE_SEEDS: '$r' is not a seed (a non-negative integer)" >&2; exit 1; }
done
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"
: > "$work/rows.tsv"

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
  /usr/bin/python3 - "$out" "$label" "$name" "$work/rows.tsv" <<'PY'
import json, sys
out, label, name, rows = sys.argv[1:]
e = json.load(open(out + "/eval.json"))
r = json.load(open(out + "/run.json"))["stages"]["refine"]
corr = e.get("correspondences", {}).get("distance_m", {}).get("rmse")
d = e["rotation_drift_deg"]
print(f"{label:34s} {name:18s} {e['ate_m']['rmse']:8.4f} {corr if corr is not None else float('nan'):8.4f} "
      f"{d['max']:8.2f} {d['rmse']:8.3f} {r['ms_per_frame']:8.1f} {e['rotation_drift_p99_deg']:8.2f} "
      f"{e['rotation_drift_smoothed_deg']['max']:8.2f}", flush=True)
with open(rows, "a") as f:
    f.write(f"{label}\t{name}\t{e['ate_m']['rmse']}\t{corr if corr is not None else float('nan')}\t{d['max']}\t{d['rmse']}\t{r['ms_per_frame']}\n")
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
      for r in "${refine_seeds[@]}"; do
        label="$scene-$seed"
        [ "${#refine_seeds[@]}" -gt 1 ] && label="$label/r$r"
        # shellcheck disable=SC2086
        row "$label" "$sim" "$out" "$name" $args --refine-seed "$r"
      done
    done
  done
done

# Each walk scene's means over its walks (and refinement seeds), per variant.
echo
/usr/bin/python3 - "$work/rows.tsv" <<'PY'
import collections, re, sys
groups = collections.defaultdict(list)
for line in open(sys.argv[1]):
    label, name, *v = line.rstrip("\n").split("\t")
    m = re.match(r"(two-rooms|apartment-square|apartment)-\d+", label)
    if m: groups[(m.group(1), name)].append([float(x) for x in v])
print(f"{'scene (mean)':34s} {'variant':18s} {'ATE m':>8s} {'corr m':>8s} {'drift^':>8s} {'driftRMS':>8s} {'ms/fr':>8s} {'runs':>8s} {'worst^':>8s}")
for (scene, name), rows in groups.items():
    mean = [sum(r[i] for r in rows) / len(rows) for i in range(5)]
    print(f"{scene:34s} {name:18s} {mean[0]:8.4f} {mean[1]:8.4f} {mean[2]:8.3f} {mean[3]:8.3f} {mean[4]:8.1f} "
          f"{len(rows):8d} {max(r[2] for r in rows):8.2f}")
PY

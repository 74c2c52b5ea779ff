#!/usr/bin/env bash
# How register's cost and accuracy grow with the length of a scan: one simulated apartment
# walk, registered cold (no cache) on prefixes of it (--last), with each stage's time per
# frame, the whole run's peak memory, the caches' size per frame and the accuracy (ATE,
# correspondence RMSE, worst rotation drift over pairs 5 s or more apart) of T0 and of the
# result. Prints BENCHMARKS.md's growth table.
#
# Usage: bash bench/growth_bench.sh [build dir] [work dir]
#   F2C_GROWTH_PREFIXES  frames of each prefix, ascending (default "900 3000 7500 15000";
#                        the 15,000-frame run takes about an hour here)
#   F2C_GROWTH_SEED      the walk's seed (default 0)
set -euo pipefail
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"
read -r -a prefixes <<< "${F2C_GROWTH_PREFIXES:-900 3000 7500 15000}"
seed="${F2C_GROWTH_SEED:-0}"
longest="${prefixes[${#prefixes[@]}-1]}"
sim="$work/apartment-$longest-$seed"
[ -f "$sim/rgb.txt" ] || "$bin" simulate --scene apartment --frames "$longest" --seed "$seed" -o "$sim" -q > /dev/null

for frames in "${prefixes[@]}"; do
  out="$work/growth-$frames"
  rm -rf "$out"
  last=$((frames - 1))
  "$bin" register "$sim" --last "$last" -o "$out" -q --no-report > /dev/null
  for t in trajectory trajectory_t0; do
    "$bin" evaluate --json --estimate "$out/$t.txt" --ground-truth "$sim" --last "$last" > "$out/eval_$t.json"
  done
done

python3 - "$work" "${prefixes[@]}" <<'PY'
import json, os, sys
work, prefixes = sys.argv[1], sys.argv[2:]
print("| frames | odometry + features ms/frame | refinement ms/frame | mesh ms/frame | whole run frames/s "
      "| peak memory (MiB) | feature cache KB/frame | keyframe cache KB/frame | ATE T0 -> refined (m) "
      "| corr. RMSE T0 -> refined (m) | worst rotation drift T0 -> refined (deg) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for frames in prefixes:
    out = os.path.join(work, f"growth-{frames}")
    run = json.load(open(os.path.join(out, "run.json")))
    ev = json.load(open(os.path.join(out, "eval_trajectory.json")))
    ev0 = json.load(open(os.path.join(out, "eval_trajectory_t0.json")))
    n = run["frames"]
    stages = run["stages"]
    ms = lambda stage: 1000.0 * stages[stage]["wall_s"] / n if stages.get(stage) else float("nan")
    size = lambda name: os.path.getsize(os.path.join(out, "cache", name)) / 1000.0 / n \
        if os.path.exists(os.path.join(out, "cache", name)) else float("nan")
    stat = lambda e, key: e[key]["rmse"] if e.get(key) and e[key]["rmse"] is not None else float("nan")
    corr = lambda e: e["correspondences"]["distance_m"]["rmse"] if "correspondences" in e else float("nan")
    drift = lambda e: e["rotation_drift_deg"]["max"] if e["rotation_drift_deg"]["max"] is not None else float("nan")
    print(f"| {n} | {ms('odometry') + ms('features'):.1f} | {ms('refine'):.1f} | {ms('fusion'):.1f} "
          f"| {n / run['total_wall_s']:.1f} | {run['peak_memory_bytes'] / 2**20:.0f} "
          f"| {size('features.f2cf'):.0f} | {size('keyframes.f2ck'):.1f} "
          f"| {stat(ev0, 'ate_m'):.4f} -> {stat(ev, 'ate_m'):.4f} | {corr(ev0):.4f} -> {corr(ev):.4f} "
          f"| {drift(ev0):.2f} -> {drift(ev):.2f} |")
PY

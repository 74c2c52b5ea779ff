#!/usr/bin/env bash
# Mesh accuracy and completeness against the simulator's true surfaces (issue 11): simulated
# two-rooms and apartment, 900 frames at 30 Hz, seeds 0-2; register (refined poses, mesh.ply)
# and the same frames fused at T0's poses; evaluate --mesh for both.
#
#   bash bench/mesh_accuracy_bench.sh [build dir] [work dir]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
for scene in two-rooms apartment; do
  for seed in 0 1 2; do
    sim="$work/sim-$scene-$seed"
    [ -f "$sim/scene.ply" ] || "$bin" simulate --scene "$scene" --frames 900 --seed "$seed" -o "$sim" -q > /dev/null
    out="$work/reg-$scene-$seed"
    [ -f "$out/mesh.ply" ] || "$bin" register "$sim" -o "$out" -q > /dev/null
    "$bin" fuse "$sim" --trajectory "$out/trajectory_t0.txt" -o "$out/mesh_t0.ply" -q > /dev/null
    "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$sim" --mesh "$out/mesh.ply" > "$out/eval_mesh.json"
    "$bin" evaluate --json --estimate "$out/trajectory_t0.txt" --ground-truth "$sim" --mesh "$out/mesh_t0.ply" \
      > "$out/eval_mesh_t0.json"
  done
done
/usr/bin/python3 - "$work" <<'PY'
import json, statistics as st, sys
work = sys.argv[1]
print("| scene | seed | ATE T0 / final (m) | accuracy mean T0 / final (m) | median | 90th percentile | far (> 0.25 m) | completeness T0 / final |")
print("|---|---|---|---|---|---|---|---|")
runs = []
for scene in ("two-rooms", "apartment"):
    for seed in range(3):
        d = f"{work}/reg-{scene}-{seed}"
        t, f = json.load(open(d + "/eval_mesh_t0.json")), json.load(open(d + "/eval_mesh.json"))
        tm, fm = t["mesh"], f["mesh"]
        runs.append((tm, fm))
        print(f"| {scene} | {seed} | {t['ate_m']['rmse']:.3f} / {f['ate_m']['rmse']:.3f} | "
              f"{tm['accuracy_m']['mean']:.3f} / {fm['accuracy_m']['mean']:.3f} | "
              f"{tm['accuracy_m']['median']:.3f} / {fm['accuracy_m']['median']:.3f} | "
              f"{tm['accuracy_p90_m']:.3f} / {fm['accuracy_p90_m']:.3f} | "
              f"{100 * tm['far_fraction']:.1f}% / {100 * fm['far_fraction']:.1f}% | "
              f"{100 * tm['completeness']:.1f}% / {100 * fm['completeness']:.1f}% |")
mean = lambda i, get: st.mean(get(r[i]) for r in runs)
cols = [lambda m: m["accuracy_m"]["mean"], lambda m: m["accuracy_m"]["median"], lambda m: m["accuracy_p90_m"]]
cells = " | ".join(f"{mean(0, g):.3f} / {mean(1, g):.3f}" for g in cols)
print(f"| **mean** | | | {cells} | {100 * mean(0, lambda m: m['far_fraction']):.1f}% / "
      f"{100 * mean(1, lambda m: m['far_fraction']):.1f}% | {100 * mean(0, lambda m: m['completeness']):.1f}% / "
      f"{100 * mean(1, lambda m: m['completeness']):.1f}% |")
PY

#!/usr/bin/env bash
# The refinement's results table (issue 8): accuracy and speed of T0 and of the refinement
# with its variants, on the real sequences and on simulated multi-room walks, and how time
# and memory grow with the number of frames.
#
#   bash bench/refine_bench.sh [build dir] [work dir]
#
# Real data: ../shared/data/tum_fr1_xyz_15hz and 7scenes_redkitchen_15hz (skipped if absent).
# Simulated: two-rooms and apartment, 900 frames (30 s at 30 Hz), seeds 0, 1, 2; and an
# apartment walk of 5,000 frames registered at 500, 1,000, 2,000 and 5,000 frames.
# The work dir keeps simulations and caches between runs (default: a fresh temporary one).
# Each variant re-runs register into the same output folder, so the odometry and features
# come from the cache and the timings are the refinement's own.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
data="$(pwd)/../shared/data"
results="$work/results.txt"
: > "$results"

variants=(
  "default|"
  "paper: no SIFT loops, no polish, no E_V|--no-sift-loops --polish-iterations 0 --weight-velocity 0"
  "no steady motion (E_V)|--weight-velocity 0"
  "no SIFT loops|--no-sift-loops"
  "no polish iterations|--polish-iterations 0"
  "windows by path (authors)|--windows path"
  "solve to convergence|--solve converge"
  "l_0 = 4|--window-frames 4"
  "l_0 = 16|--window-frames 16"
  "l_0 = 32|--window-frames 32"
  "conjugate gradients|--linear-solver cgnr"
)

row=0
run() {  # name dataset_dir out_dir extra...; keeps the row's run.json and evaluations
  local name="$1" dir="$2" out="$3"
  shift 3
  "$bin" register "$dir" -o "$out" -q --no-mesh "$@" > "$out.log" 2>&1
  row=$((row + 1))
  local keep="$work/rows/$row"
  mkdir -p "$keep"
  cp "$out/run.json" "$keep/"
  "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$dir" > "$keep/eval.json"
  "$bin" evaluate --json --estimate "$out/trajectory_t0.txt" --ground-truth "$dir" > "$keep/eval_t0.json"
  echo "$name|$dir|$out|$keep" >> "$results"
}

# Real sequences: a first run with no cache gives the end-to-end rate.
for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent"; continue; }
  extra=()
  [ "$seq" = tum_fr1_xyz_15hz ] && extra=(--intrinsics tum-fr1)
  out="$work/real-$seq"
  rm -rf "$out"
  run "end-to-end" "$data/$seq" "$out" "${extra[@]}"
  "$bin" register "$data/$seq" -o "$out" -q --no-mesh "${extra[@]}" > /dev/null 2>&1  # warm-up: keyframes cached
  for v in "${variants[@]}"; do
    IFS='|' read -r name args <<< "$v"
    # shellcheck disable=SC2086
    run "$name" "$data/$seq" "$out" "${extra[@]}" $args
  done
done

# Simulated walks.
for scene in two-rooms apartment; do
  for seed in 0 1 2; do
    sim="$work/sim-$scene-$seed"
    [ -f "$sim/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames 900 --seed "$seed" -o "$sim" -q > /dev/null
    # Warm-up: odometry, features and keyframes into the cache, so every row below times the
    # refinement alone.
    "$bin" register "$sim" -o "$work/out-$scene-$seed" -q --no-mesh --polish-iterations 0 --extra-iterations 0 > /dev/null 2>&1
    for v in "${variants[@]}"; do
      IFS='|' read -r name args <<< "$v"
      # shellcheck disable=SC2086
      run "$name" "$sim" "$work/out-$scene-$seed" $args
    done
  done
done

# Growth with frames: prefixes of one 5,000-frame apartment walk, default options.
big="$work/sim-apartment-5000"
[ -f "$big/rgb.txt" ] || "$bin" simulate --scene apartment --frames 5000 --seed 0 -o "$big" -q > /dev/null
for n in 500 1000 2000 5000; do
  "$bin" register "$big" -o "$work/big-$n" -q --no-mesh --last $((n - 1)) --polish-iterations 0 --extra-iterations 0 > /dev/null 2>&1
  run "frames $n" "$big" "$work/big-$n" --last $((n - 1))
done

/usr/bin/python3 - "$results" <<'PY'
import json, sys
from collections import defaultdict, OrderedDict
rows = [l.rstrip("\n").split("|") for l in open(sys.argv[1])]
def load(out):  # a kept row
    run = json.load(open(out + "/run.json"))
    ev = json.load(open(out + "/eval.json"))
    ev0 = json.load(open(out + "/eval_t0.json"))
    refine = run["stages"]["refine"] or {}
    corr = lambda e: e["correspondences"]["distance_m"]["rmse"] if "correspondences" in e else float("nan")
    return dict(ate=ev["ate_m"]["rmse"], ate0=ev0["ate_m"]["rmse"], corr=corr(ev), corr0=corr(ev0),
                ms=refine.get("ms_per_frame", float("nan")), frames=run["frames"], wall=run["total_wall_s"],
                peak=run["peak_memory_bytes"] / 2**20, refine_peak=refine.get("peak_memory_bytes_after", 0) / 2**20,
                iterations=len(refine.get("iterations", [])))
real = OrderedDict()
sims = defaultdict(lambda: defaultdict(list))
growth = []
for name, d, out, keep in rows:
    r = load(keep)
    if "/real-" in out:
        real.setdefault(name, {})[d.rstrip("/").split("/")[-1]] = r
    elif "/out-" in out:
        scene = "two-rooms" if "two-rooms" in out else "apartment"
        sims[name][scene].append(r)
    else:
        growth.append((name, r))
print("### Real sequences (ATE RMSE, m; refinement ms per input frame)\n")
print("| variant | fr1/xyz ATE | redkitchen ATE | fr1/xyz ms/frame | redkitchen ms/frame | iterations |")
print("|---|---|---|---|---|---|")
for name, by in real.items():
    x, k = by.get("tum_fr1_xyz_15hz"), by.get("7scenes_redkitchen_15hz")
    f = lambda r, key, fmt: (fmt % r[key]) if r else "-"
    if name == "end-to-end":
        print(f"| T0 | {f(x,'ate0','%.4f')} | {f(k,'ate0','%.4f')} | | | |")
        print(f"| register end to end, no cache: frames/s | {x and '%.1f' % (x['frames']/x['wall'])} | "
              f"{k and '%.1f' % (k['frames']/k['wall'])} | | | |")
        continue
    print(f"| {name} | {f(x,'ate','%.4f')} | {f(k,'ate','%.4f')} | {f(x,'ms','%.1f')} | {f(k,'ms','%.1f')} | "
          f"{(x or k)['iterations']} |")
print("\n### Simulated walks, 900 frames, seeds 0/1/2 (means; ratio = T0 / refined)\n")
print("| variant | two-rooms ATE (T0 -> refined, ratio) | two-rooms corr. RMSE | apartment ATE | apartment corr. RMSE | ms/frame |")
print("|---|---|---|---|---|---|")
mean = lambda v: sum(v) / len(v)
for name, by in sims.items():
    cells = []
    ms = []
    for scene in ("two-rooms", "apartment"):
        rs = by[scene]
        for a, b in (("ate0", "ate"), ("corr0", "corr")):
            t0, fin = mean([r[a] for r in rs]), mean([r[b] for r in rs])
            cells.append(f"{t0:.3f} -> {fin:.3f} ({t0 / fin:.1f}x)")
        ms += [r["ms"] for r in rs]
    print(f"| {name} | " + " | ".join(cells) + f" | {mean(ms):.1f} |")
print("\n### Growth with frames (apartment walk, default options)\n")
print("| frames | refinement ms/frame | refinement s | peak memory (MiB) | T0 ATE | refined ATE | T0 corr. | refined corr. |")
print("|---|---|---|---|---|---|---|---|")
for name, r in growth:
    print(f"| {r['frames']} | {r['ms']:.1f} | {r['ms'] * r['frames'] / 1000:.1f} | {r['peak']:.0f} | {r['ate0']:.3f} | "
          f"{r['ate']:.3f} | {r['corr0']:.3f} | {r['corr']:.3f} |")
PY

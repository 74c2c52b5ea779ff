#!/usr/bin/env bash
# Are off-square rooms kept off-square? (issue 9) The apartment's living room is a trapezoid
# whose side walls are 14 deg off square (apartment) or 6 deg (apartment-square); the walk
# reaches it after about 52 s, so 2,001 frames (67 s) are simulated. Each is registered
# without and with the structural model, and bench/wall_angles measures the angle between
# the room's walls as T0 and each result place them.
#
#   bash bench/wall_angles.sh [build dir] [work dir]
#
# F2C_BENCH_SEEDS: the walks' seeds (default "0"); seed 0 keeps the folder names of earlier
# runs, others get -sSEED. F2C_BENCH_VARIANTS: more variants after the two, each NAME=ARGS
# separated by ';' (e.g. "loss1=--structure --polish-relation-loss-scale 1"); they reuse the
# walk's caches.
set -euo pipefail
cd "$(dirname "$0")/.."
build="$(pwd)/${1:-build}"
bin="$build/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
declare -A skew=([apartment]=1.0 [apartment-square]=0.420417)  # scene.cc: 4 tan(6 deg)
for seed in ${F2C_BENCH_SEEDS:-0}; do
suffix=""
[ "$seed" = 0 ] || suffix="-s$seed"
for scene in apartment apartment-square; do
  sim="$work/sim-$scene-2001$suffix"
  [ -f "$sim/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames 2001 --seed "$seed" -o "$sim" -q > /dev/null
  s=${skew[$scene]}
  walls=(--wall right 10 6 "$(awk "BEGIN {print 10 - $s}")" 10 --wall back "$(awk "BEGIN {print 10 - $s}")" 10 "$(awk "BEGIN {print 2 + $s}")" 10
         --wall left "$(awk "BEGIN {print 2 + $s}")" 10 2 6)
  variants=("no-structure=--no-structure" "structure=--structure")
  IFS=';' read -r -a more <<< "${F2C_BENCH_VARIANTS:-}"
  variants+=("${more[@]}")
  for v in "${variants[@]}"; do
    variant="${v%%=*}"
    out="$work/out-$scene$suffix-$variant"
    mkdir -p "$out"
    [ -d "$work/out-$scene$suffix-no-structure/cache" ] && [ ! -d "$out/cache" ] && cp -r "$work/out-$scene$suffix-no-structure/cache" "$out/"
    # shellcheck disable=SC2086
    "$bin" register "$sim" -o "$out" -q --no-mesh ${v#*=} > "$out.log" 2>&1
    if [ "$variant" = no-structure ]; then
      echo "## $scene, seed $seed, T0"
      "$build/bench/wall_angles" "$sim" "$out/cache/features.f2cf" "$out/trajectory_t0.txt" "${walls[@]}"
    fi
    label="--$variant"
    [ "$v" = "$variant=--$variant" ] || label="$variant (${v#*=})"
    echo "## $scene, seed $seed, $label"
    "$build/bench/wall_angles" "$sim" "$out/cache/features.f2cf" "$out/trajectory.txt" "${walls[@]}"
  done
done
done

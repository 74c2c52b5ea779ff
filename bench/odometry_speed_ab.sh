#!/usr/bin/env bash
# Speed of T0 and the features (register --stop-after odometry --no-cache) of two builds on
# the six simulated 30 Hz walks (two-rooms and apartment, 900 frames, seeds 0-2), the two
# run in turn on each walk so that both see the same machine (its speed drifts by 10-20%
# between minutes here). Prints seconds per walk and the total, and the speed-up.
#
#   bash bench/odometry_speed_ab.sh OLD_BINARY NEW_BINARY [work dir]
#
# OLD_BINARY, e.g. commit 8a0c7f5 (before keyframe odometry):
#   git worktree add /tmp/old 8a0c7f5 && cmake -S /tmp/old -B /tmp/old/build -G Ninja \
#     -DCMAKE_BUILD_TYPE=Release -DF2C_BUILD_TESTS=OFF && cmake --build /tmp/old/build --target fine2coarse
set -euo pipefail
old="$1"; new="$2"; work="${3:-$(mktemp -d)}"
mkdir -p "$work"
total_old=0; total_new=0
printf '| walk | old (s) | new (s) | speed-up |\n|---|---|---|---|\n'
for scene in two-rooms apartment; do
  for seed in 0 1 2; do
    sim="$work/sim-$scene-$seed"
    [ -f "$sim/groundtruth.txt" ] || "$new" simulate --scene "$scene" --frames 900 --seed "$seed" -o "$sim" -q > /dev/null
    declare -A t
    for which in old new; do
      bin="$old"; [ $which = new ] && bin="$new"
      out="$work/$scene-$seed-$which"
      rm -rf "$out"
      "$bin" register "$sim" -o "$out" -q --no-cache --stop-after odometry > /dev/null 2>&1
      t[$which]=$(/usr/bin/python3 -c "import json; print(json.load(open('$out/run.json'))['total_wall_s'])")
    done
    total_old=$(/usr/bin/python3 -c "print($total_old + ${t[old]})")
    total_new=$(/usr/bin/python3 -c "print($total_new + ${t[new]})")
    /usr/bin/python3 -c "print(f'| $scene $seed | {${t[old]}:.2f} | {${t[new]}:.2f} | {${t[old]}/${t[new]}:.2f} |')"
  done
done
/usr/bin/python3 -c "print(f'| **all** | **{$total_old:.1f} ({1000*$total_old/5400:.1f} ms/frame)** | **{$total_new:.1f} ({1000*$total_new/5400:.1f} ms/frame)** | **{$total_old/$total_new:.2f}** |')"

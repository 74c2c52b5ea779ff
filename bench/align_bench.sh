#!/usr/bin/env bash
# --align-to depth against --align-to color on recordings whose colour is another camera
# (bench/two_camera_sens: four configurations of a simulated walk with exact poses): T0's and
# the refinement's ATE, each against the recording's poses expressed for the camera the run
# sees from (evaluate --align-to the same).
#   bash bench/align_bench.sh BUILD OUT
set -euo pipefail
build=$1 out=$2
mkdir -p "$out"
ate() {
  "$build/apps/fine2coarse" evaluate --json --align-to "$1" --estimate "$2" --ground-truth "$3" |
    /usr/bin/python3 -c "import json,sys; print('%.5f' % json.load(sys.stdin)['ate_m']['rmse'])"
}
echo "| recording | --align-to | T0 ATE (m) | refined ATE (m) | register (s) |"
echo "|---|---|---|---|---|"
for c in 0 1 2 3; do
  "$build/bench/two_camera_sens" "$out/two_cameras_$c.sens" "$c"
  for a in depth color; do
    start=$(date +%s.%N)
    "$build/apps/fine2coarse" register "$out/two_cameras_$c.sens" -q --no-report --no-mesh --align-to "$a" \
      -o "$out/run_${c}_$a" > /dev/null
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    echo "| config $c | $a | $(ate "$a" "$out/run_${c}_$a/trajectory_t0.txt" "$out/two_cameras_$c.sens") |" \
         "$(ate "$a" "$out/run_${c}_$a/trajectory.txt" "$out/two_cameras_$c.sens") | $(printf %.1f "$seconds") |"
  done
done

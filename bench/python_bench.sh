#!/usr/bin/env bash
# The Python module against the command line: each real sequence registered end to end with
# no cache, no mesh and no report, once by `fine2coarse register` and once by
# fine2coarse.register() (the import included), one after the other on the same machine.
# Prints the wall time of each and whether the poses agree (to the TUM file's 9 decimals).
#
#   bash bench/python_bench.sh [build dir] [work dir]
set -euo pipefail
cd "$(dirname "$0")/.."
# shellcheck source=bench/bench_env.sh
source bench/bench_env.sh "$@"
module_dir="$(pwd)/${1:-build}/python"
[ -d "$module_dir" ] || { echo "error: $module_dir not found: build with -DF2C_PYTHON=ON" >&2; exit 1; }

echo "| dataset | frames | fine2coarse register (s) | fine2coarse.register() (s) | largest pose difference (m) |"
echo "|---|---|---|---|---|"
for seq in tum_fr1_xyz_15hz tum_fr1_desk_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skipping $seq: $data/$seq is absent" >&2; continue; }
  intrinsics=""
  [[ "$seq" == tum_* ]] && intrinsics=tum-fr1
  out="$work/$seq-cli"
  rm -rf "$out"
  start=$(date +%s.%N)
  "$bin" register "$data/$seq" -o "$out" -q --no-cache --no-mesh --no-report ${intrinsics:+--intrinsics "$intrinsics"} \
    > /dev/null
  cli_s=$(echo "$(date +%s.%N) - $start" | bc)
  PYTHONPATH="$module_dir" /usr/bin/python3 - "$data/$seq" "$intrinsics" "$out/trajectory.txt" "$seq" "$cli_s" <<'PY'
import sys, time
start = time.time()
import fine2coarse
import numpy as np
path, intrinsics, cli_file, name, cli_s = sys.argv[1:]
r = fine2coarse.register(path, **({"intrinsics": intrinsics} if intrinsics else {}))
seconds = time.time() - start
rows = np.loadtxt(cli_file)
diff = np.abs(r.poses[:, :3, 3] - rows[:, 1:4]).max()
print("| %s | %d | %.1f | %.1f | %.1g |" % (name, len(r.poses), float(cli_s), seconds, diff))
PY
done

#!/usr/bin/env bash
# TSDF fusion speed and memory (issue 11): fine2coarse fuse beside Open3D 0.16's
# ScalableTSDFVolume (legacy) and VoxelBlockGrid (tensor, CPU), on the same frames and
# poses (the refined trajectory.conf of a register run), at 1 cm and 2 cm voxels, depth up
# to 4 m, truncation 4 voxels, images read included. Open3D runs only where python3-open3d
# is installed. Each configuration runs `reps` times, the three tools in turn; the table
# gives the median.
#
#   bash bench/fusion_bench.sh [build dir] [work dir] [reps]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
reps="${3:-3}"
mkdir -p "$work"
data="$(pwd)/../shared/data"
have_open3d=0
/usr/bin/python3 -c "import open3d" 2>/dev/null && have_open3d=1
[ $have_open3d = 1 ] || echo "python3-open3d absent: fine2coarse only" >&2
results="$work/results.txt"
: > "$results"

for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz; do
  [ -d "$data/$seq" ] || { echo "skip $seq: $data/$seq absent" >&2; continue; }
  k=(); scale=1000
  if [ -f "$data/$seq/rgb.txt" ]; then k=(--intrinsics tum-fr1); scale=5000; fi
  reg="$work/$seq-register"
  [ -f "$reg/trajectory.conf" ] || "$bin" register "$data/$seq" "${k[@]}" -o "$reg" -q --no-mesh > /dev/null
  for voxel in 0.01 0.02; do
    for rep in $(seq "$reps"); do
      out="$work/$seq-$voxel-$rep"
      "$bin" fuse "$data/$seq" "${k[@]}" --trajectory "$reg/trajectory.conf" --voxel-size "$voxel" \
        -o "$out-ours.ply" -q --json > "$out-ours.json"
      echo "$seq $voxel ours $out-ours.json" >> "$results"
      if [ $have_open3d = 1 ]; then
        for kind in legacy tensor; do
          /usr/bin/python3 bench/fusion_open3d.py "$reg/trajectory.conf" "$scale" "$voxel" "$kind" "$out-$kind.ply" \
            2> /dev/null | tail -1 > "$out-$kind.json"
          echo "$seq $voxel $kind $out-$kind.json" >> "$results"
        done
      fi
    done
  done
done

/usr/bin/python3 - "$results" <<'PY'
import json, statistics, sys
from collections import defaultdict
runs = defaultdict(list)
for line in open(sys.argv[1]):
    seq, voxel, tool, path = line.split()
    runs[(seq, voxel, tool)].append(json.load(open(path)))
names = {"ours": "fine2coarse", "legacy": "Open3D ScalableTSDFVolume", "tensor": "Open3D VoxelBlockGrid"}
print("| sequence | voxel | tool | ms per frame (integration, images read) | mesh (s) | triangles | peak memory (MiB) | vs the faster Open3D |")
print("|---|---|---|---|---|---|---|---|")
for (seq, voxel) in sorted({(s, v) for s, v, _ in runs}):
    ms = {}
    for tool in ("ours", "legacy", "tensor"):
        r = runs.get((seq, voxel, tool))
        if not r:
            continue
        frames = r[0].get("frames_fused", r[0].get("frames"))
        ms[tool] = statistics.median(1000 * x["integrate_s"] / frames for x in r)
    fastest = min((ms[t] for t in ("legacy", "tensor") if t in ms), default=None)
    for tool in ("ours", "legacy", "tensor"):
        r = runs.get((seq, voxel, tool))
        if not r:
            continue
        mesh = statistics.median(x.get("mesh_s") for x in r)
        speedup = f"{fastest / ms[tool]:.1f}x" if fastest else ""
        print(f"| {seq} | {float(voxel) * 100:.0f} cm | {names[tool]} | {ms[tool]:.1f} | {mesh:.2f} | "
              f"{r[0]['triangles']} | {r[0]['peak_memory_bytes'] / 2**20:.0f} | {speedup} |")
PY

#!/usr/bin/env bash
# Planar proxies and features per frame, and extraction time, on every sequence in
# ../shared/data (fresh runs, default options). Time per frame per core is the CPU time of
# the extraction itself (summed over threads, divided by frames); depth decoding is listed
# apart; frames/s is the wall rate of the whole command on this machine (all cores).
#   bash bench/features_bench.sh [build dir]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/apps/fine2coarse"
data=../shared/data
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '| sequence | frames | proxies | plane | silhouette | shadow | border | ridge | valley | extraction (ms/frame/core) | decode (ms/frame/core) | frames/s (wall) |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for seq in tum_fr1_xyz_15hz 7scenes_redkitchen_15hz tum_fr1_desk_9 sun3d_mit76_studyroom_5 open3d_testdata_rgbd; do
  [ -d "$data/$seq" ] || { echo "skip $seq: $data/$seq absent" >&2; continue; }
  k=(); [ -f "$data/$seq/rgb.txt" ] && k=(--intrinsics tum-fr1)
  start=$(date +%s.%N)
  "$bin" features "$data/$seq" -o "$tmp/$seq" "${k[@]}" -q >/dev/null
  end=$(date +%s.%N)
  /usr/bin/python3 - "$seq" "$tmp/$seq/features.json" "$start" "$end" <<'PY'
import json, sys
seq, path, start, end = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
r = json.load(open(path)); f = r["statistics"]["per_frame"]; t = r["timings"]; n = r["frames"]
print(f"| {seq} | {n} | {f['proxies']:.1f} | {f['plane']:.0f} | {f['silhouette']:.0f} | {f['shadow']:.0f} | "
      f"{f['border']:.0f} | {f['ridge']:.1f} | {f['valley']:.1f} | {t['extract_ms_per_frame_per_core']:.1f} | "
      f"{1000 * t['decode_cpu_s'] / n:.1f} | {n / (end - start):.0f} |")
PY
done

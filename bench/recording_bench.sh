#!/usr/bin/env bash
# Read speed and memory of the recording formats beside the folder they were written from:
# the folder itself, a ScanNet .sens (bench/sens_bench: zlib depth, the folder's colour) and
# ROS 1 bags written by python3-rosbag (tests/tools/write_rosbag.py: TUM's bag layout, raw
# rgb8 colour and 32FC1 depth; uncompressed, lz4, bz2) and ROS 2 bags (bench/write_ros2:
# SQLite .db3, MCAP with each chunk compression). Each row opens the input as register
# does and decodes every frame's depth and colour on one thread (bench/read_bench). The last
# row is a bag of the frames repeated to at least BIG_GB (default 5) gigabytes: its peak
# memory against the folder's shows that a recording is streamed, not loaded.
#
#   bash bench/recording_bench.sh BUILD OUT TUM_FOLDER INTRINSICS [BIG_GB]
#   e.g. bash bench/recording_bench.sh build /tmp/rec ../shared/data/tum_fr1_desk_15hz 517.3,516.5,318.6,255.3
set -euo pipefail
build=$1 out=$2 folder=$3 k=$4 big_gb=${5:-5}
here="$(cd "$(dirname "$0")/.." && pwd)"
python=/usr/bin/python3
mkdir -p "$out"
echo "| input | frames | open (s) | frames/s decoded | size (GB) | peak memory (MiB) |"
echo "|---|---|---|---|---|---|"
"$build/bench/read_bench" "$folder" "warm-up" --intrinsics "$k" > /dev/null  # the folder's files into the page cache
"$build/bench/read_bench" "$folder" "folder (the dataset's files)" --intrinsics "$k"
"$build/bench/sens_bench" "$folder" "$out/scan.sens" --intrinsics "$k" > /dev/null
"$build/bench/read_bench" "$out/scan.sens" ".sens (zlib depth, the folder's colour files)" --intrinsics "$k"
for c in none lz4 bz2; do
  "$python" "$here/tests/tools/write_rosbag.py" "$folder" "$out/$c.bag" --intrinsics "$k" --compression "$c"
  "$build/bench/read_bench" "$out/$c.bag" "ROS bag, chunks $c (raw rgb8, 32FC1)" --intrinsics "$k"
done
for f in "db3 none" "mcap none" "mcap zstd" "mcap lz4"; do
  set -- $f
  "$build/bench/write_ros2" "$folder" "$out/ros2_$1_$2" "$1" "$2" "$k"
  "$build/bench/read_bench" "$out/ros2_$1_$2" "ROS 2 bag, $1, chunks $2 (raw rgb8, 32FC1)" --intrinsics "$k"
done
# Repeats of the frames until the bag is at least big_gb gigabytes.
per_copy=$(stat -c %s "$out/none.bag")
repeat=$(( (big_gb * 1000000000 + per_copy - 1) / per_copy ))
"$python" "$here/tests/tools/write_rosbag.py" "$folder" "$out/big.bag" --intrinsics "$k" --repeat "$repeat"
"$build/bench/read_bench" "$out/big.bag" "ROS bag, the frames $repeat times" --intrinsics "$k"
rm -f "$out/big.bag"

#!/usr/bin/env bash
# Sets up, builds, registers a real sequence into T0 and evaluates it against ground truth.
#   bash scripts/demo.sh [DATASET] [OUTDIR] [register options...]
# Default: TUM fr1/xyz from ../shared/data with the fr1 intrinsics.
set -euo pipefail
cd "$(dirname "$0")/.."
input="${1:-../shared/data/tum_fr1_xyz_15hz}"
out="${2:-out/$(basename "$input")}"
shift $(( $# > 2 ? 2 : $# ))
extra=("$@")
if [ ${#extra[@]} -eq 0 ] && [ -f "$input/rgb.txt" ]; then extra=(--intrinsics tum-fr1); fi
bash scripts/build.sh
./build/apps/fine2coarse register "$input" -o "$out" "${extra[@]}"
./build/apps/fine2coarse evaluate --estimate "$out/trajectory.txt" --ground-truth "$input"

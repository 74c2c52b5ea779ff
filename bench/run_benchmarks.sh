#!/usr/bin/env bash
# BENCHMARKS.md's main tables in one command: every real sequence with ground truth in
# ../shared/data, simulated multi-room walks and object scans, through T0, the refinement and its
# ablations, with Open3D's reconstruction system run beside us as a peer where Debian's
# python3-open3d and python3-joblib are installed (`bash scripts/setup.sh --peers`).
#
#   bash bench/run_benchmarks.sh [build dir] [work dir]
#
# Writes WORK/tables.md (Markdown, also printed) and WORK/report.html (the tables, then one
# page per dataset: trajectories, errors, Fig. 9 and the top-down slice for T0, the peer and
# the result). The work dir keeps simulations between runs (default: a fresh temporary one).
#
# Environment:
#   F2C_BENCH_SEEDS    simulated seeds (default "0 1 2")
#   F2C_BENCH_FRAMES   frames per simulated walk (default 900: 30 s at 30 Hz)
#   F2C_BENCH_DATA    the real sequences' folder (default ../shared/data)
#   F2C_BENCH_PEER     open3d (default): the peer on the real sequences; open3d-all: on the
#                      simulated walks too (about 15 minutes per 900-frame walk here); off
#
# Each dataset is registered once end to end with no cache (odometry, refinement, mesh and
# report: the time a user waits), then once per ablation into the same folder, where the
# odometry and features come from the cache (--no-mesh --no-report: the refinement's own
# time). Runs that fail are listed as failed, not dropped.
set -uo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
bin="$root/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
work="$(cd "$work" && pwd)"
data="${F2C_BENCH_DATA:-$root/../shared/data}"
seeds="${F2C_BENCH_SEEDS:-0 1 2}"
frames="${F2C_BENCH_FRAMES:-900}"
peer="${F2C_BENCH_PEER:-open3d}"
rows="$work/rows.tsv"  # kind, dataset label, variant, kept folder
: > "$rows"
[ -x "$bin" ] || { echo "error: $bin not found: run bash scripts/build.sh first" >&2; exit 1; }
# The run takes about 20 minutes: a copy keeps a rebuild meanwhile from changing the binary
# under it.
cp "$bin" "$work/fine2coarse.bin" && bin="$work/fine2coarse.bin"

ablations=(
  "the paper's algorithm only|--no-sift-loops --polish-iterations 0 --weight-velocity 0 --local-information off"
  "no SIFT loops|--no-sift-loops"
  "no steady motion (E_V)|--weight-velocity 0"
  "no polish iterations|--polish-iterations 0"
  "no fine-to-coarse windows|--no-fine-to-coarse"
  "no structural model (E_P, E_H, E_G)|--no-structure"
  "no keyframes (consecutive odometry)|--keyframes off"
  "E_L one weight per link (no pair information)|--local-information off"
  "ICP fallbacks with one weight, E_V even|--local-icp-information off --velocity-unmeasured-weight 1"
)

have_peer=0
if [ "$peer" != off ]; then
  if /usr/bin/python3 -c "import open3d, joblib" 2> /dev/null; then
    have_peer=1
  else
    echo "note: Open3D's reconstruction system not run (python3-open3d and python3-joblib: bash scripts/setup.sh --peers)"
  fi
fi

# keep KIND LABEL VARIANT DATASET OUT: evaluations of OUT's trajectories into a kept folder.
keep() {
  local kind="$1" label="$2" variant="$3" dir="$4" out="$5" io="$6"
  local k="$work/rows/$(wc -l < "$rows")"
  mkdir -p "$k"
  cp "$out/run.json" "$k/"
  # shellcheck disable=SC2086
  "$bin" evaluate --json --estimate "$out/trajectory.txt" --ground-truth "$dir" $io > "$k/eval.json" &&
    "$bin" evaluate --json --estimate "$out/trajectory_t0.txt" --ground-truth "$dir" $io > "$k/eval_t0.json" || return 1
  printf '%s\t%s\t%s\t%s\n' "$kind" "$label" "$variant" "$k" >> "$rows"
}

# dataset KIND LABEL DIR IO...: the end-to-end run, the peer, the ablations and the page.
dataset() {
  local kind="$1" label="$2" dir="$3"
  shift 3
  local io="$*" out="$work/out/$label"
  rm -rf "$out"
  mkdir -p "$work/out" "$work/pages"
  echo "== $label: register, end to end"
  # shellcheck disable=SC2086
  if ! "$bin" register "$dir" -o "$out" -q $io > "$out.log" 2>&1; then
    echo "   failed: $(tail -1 "$out.log")"
    printf '%s\t%s\t%s\t%s\n' "$kind" "$label" "default" "failed" >> "$rows"
    return
  fi
  keep "$kind" "$label" "default" "$dir" "$out" "$io" || echo "   evaluation failed"
  local also=(--also "T0=$out/trajectory_t0.txt")
  local run_peer=0
  if [ $have_peer = 1 ] && { [ "$kind" = real ] || [ "$peer" = open3d-all ]; }; then run_peer=1; fi
  if [ $run_peer = 1 ]; then
    echo "== $label: Open3D's reconstruction system"
    # shellcheck disable=SC2086
    "$bin" info "$dir" $io --json > "$work/out/$label.info.json"
    if /usr/bin/python3 bench/open3d_reconstruction.py "$work/out/$label.info.json" "$work/peer/$label" \
      "$work/out/$label.open3d.log" > "$work/out/$label.open3d.json" 2> "$work/out/$label.open3d.err"; then
      local k="$work/rows/peer-$label"
      mkdir -p "$k"
      cp "$work/out/$label.open3d.json" "$k/peer.json"
      # shellcheck disable=SC2086
      if "$bin" evaluate --json --estimate "$work/out/$label.open3d.log" --ground-truth "$dir" $io > "$k/eval.json" 2> "$k/eval.err"; then
        printf '%s\t%s\t%s\t%s\n' "$kind" "$label" "open3d" "$k" >> "$rows"
        also+=(--also "Open3D=$work/out/$label.open3d.log")
      else
        echo "   Open3D's trajectory did not evaluate: $(cat "$k/eval.err")"
      fi
    else
      echo "   $(tail -1 "$work/out/$label.open3d.err")"
      printf '%s\t%s\t%s\t%s\n' "$kind" "$label" "open3d-failed" "$(tail -1 "$work/out/$label.open3d.err")" >> "$rows"
    fi
  fi
  # shellcheck disable=SC2086
  "$bin" evaluate --estimate "$out/trajectory.txt" --ground-truth "$dir" $io --name fine2coarse "${also[@]}" \
    --report "$work/pages/$label.html" > /dev/null || echo "   no page for $label"
  for a in "${ablations[@]}"; do
    IFS='|' read -r name args <<< "$a"
    echo "== $label: $name"
    # shellcheck disable=SC2086
    if "$bin" register "$dir" -o "$out" -q --no-mesh --no-report $io $args > "$out.log" 2>&1; then
      keep "$kind" "$label" "$name" "$dir" "$out" "$io" || echo "   evaluation failed"
    else
      echo "   failed: $(tail -1 "$out.log")"
      printf '%s\t%s\t%s\t%s\n' "$kind" "$label" "$name" "failed" >> "$rows"
    fi
  done
}

# Real sequences: every folder whose `info` finds a ground truth. TUM folders carry no
# intrinsics: the preset for the camera named in the folder (tum_fr1..., fr2, fr3).
for d in "$data"/*/; do
  d="${d%/}"
  seq="$(basename "$d")"
  io=""
  case "$seq" in
    tum_fr1*) io="--intrinsics tum-fr1" ;;
    tum_fr2*) io="--intrinsics tum-fr2" ;;
    tum_fr3*) io="--intrinsics tum-fr3" ;;
  esac
  # shellcheck disable=SC2086
  if ! "$bin" info "$d" $io --json > "$work/info-$seq.json" 2> "$work/info-$seq.err"; then
    echo "skipping $seq: $(cat "$work/info-$seq.err")"
    continue
  fi
  if ! grep -q '"ground_truth": "[^"]' "$work/info-$seq.json"; then
    echo "skipping $seq: no ground truth"
    continue
  fi
  # shellcheck disable=SC2086
  dataset real "$seq" "$d" $io
done
[ -d "$data" ] || echo "skipping the real sequences: $data is absent"

# Simulated scans with exact ground truth and ground-truth correspondences: walks through
# rooms, and the object scene (a table of curved and cluttered objects circled at 1-1.5 m).
for scene in two-rooms apartment object; do
  for seed in $seeds; do
    sim="$work/sim/$scene-$seed-$frames"
    [ -f "$sim/rgb.txt" ] || "$bin" simulate --scene "$scene" --frames "$frames" --seed "$seed" -o "$sim" -q > /dev/null
    dataset sim "$scene-$seed" "$sim"
  done
done

/usr/bin/python3 bench/benchmark_tables.py "$rows" "$work"

# Sourced by the benchmark scripts, from the repository root, with their arguments
# [build dir] [work dir]: sets `bin` (a copy of the built fine2coarse in the work dir, so
# that a rebuild meanwhile cannot change it), `work` (made if missing) and `data`
# (../shared/data).
# shellcheck shell=bash
bin="$(pwd)/${1:-build}/apps/fine2coarse"
work="${2:-$(mktemp -d)}"
mkdir -p "$work"
[ -x "$bin" ] || { echo "error: $bin not found: run bash scripts/build.sh first" >&2; exit 1; }
cp "$bin" "$work/fine2coarse.bin" && bin="$work/fine2coarse.bin"
data="$(pwd)/../shared/data"
export bin work data

#!/usr/bin/env bash
# Whether the C++ sources follow .clang-format; each file that does not is named, with the
# command that fixes it. Exit 77 (a skip under ctest) where clang-format is not installed.
#
#   bash scripts/check_format.sh          # check
#   bash scripts/check_format.sh --fix    # rewrite the files in place
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format > /dev/null || { echo "clang-format not installed (bash scripts/setup.sh): skipped"; exit 77; }
mapfile -t files < <(git ls-files '*.cc' '*.h' 2> /dev/null || find src apps tests bench -name '*.cc' -o -name '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i --style=file "${files[@]}"
  exit 0
fi
# One clang-format per batch of files, batches in parallel (starting it per file took most of
# the time); each file it finds unformatted is named on a line "FILE:LINE:COL: error: ...".
mapfile -t unformatted < <(printf '%s\0' "${files[@]}" |
  xargs -0 -n 32 -P "$(nproc)" clang-format --dry-run --Werror --style=file 2>&1 |
  sed -n 's/^\(.*\):[0-9]*:[0-9]*: error: code should be clang-formatted.*/\1/p' | sort -u)
for f in "${unformatted[@]}"; do
  echo "not formatted: $f (bash scripts/check_format.sh --fix)"
done
[ "${#unformatted[@]}" = 0 ] || exit 1
echo "format: ${#files[@]} files follow .clang-format"

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
bad=0
for f in "${files[@]}"; do
  if ! clang-format --dry-run --Werror --style=file "$f" > /dev/null 2>&1; then
    echo "not formatted: $f (bash scripts/check_format.sh --fix)"
    bad=1
  fi
done
[ "$bad" = 0 ] && echo "format: ${#files[@]} files follow .clang-format"
exit "$bad"

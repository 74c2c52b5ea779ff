#!/usr/bin/env bash
# The README's test command. Installs what is missing, builds the test build (clang,
# AddressSanitizer + UndefinedBehaviorSanitizer, -O2) into build-sanitize/, runs every test in
# it, then each libFuzzer target for a few seconds (scripts/test_sanitized.sh). One build, not a
# plain one and a sanitized one: every test runs where a bad read, a use after free or an
# overflow fails it, and a fresh clone is tested in under 15 minutes on 2 cores.
#
#   bash scripts/test.sh             # the sanitized suite and the fuzz smoke run
#   bash scripts/test.sh --release   # the suite in the Release build (build/, scripts/build.sh)
# Tests that need ../shared/data skip with a message when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--release" ]; then
  bash scripts/build.sh
  exec ctest --test-dir build --output-on-failure -j "$(nproc)"
fi
bash scripts/test_sanitized.sh

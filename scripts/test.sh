#!/usr/bin/env bash
# Sets up, builds and runs every test with ctest, then (unless --quick) the whole suite again
# under AddressSanitizer + UBSan with each fuzz target's smoke run (scripts/test_sanitized.sh).
# Tests that need ../shared/data skip with a message when it is absent.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
[ "${1:-}" = "--quick" ] && exit 0
bash scripts/test_sanitized.sh

#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer:
# configures and builds the asan preset (build-asan/, -O1 -g) and runs ctest
# there. Any sanitizer report aborts the process, so the test fails.
# Extra arguments go to ctest (e.g. -L unit, -R Cli).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
start=$SECONDS
cmake --preset asan
cmake --build --preset asan -j"$(nproc)"
status=0
ctest --preset asan -j"$(nproc)" "$@" || status=$?
echo "ci_asan.sh: $((SECONDS - start)) s in total (build and tests)"
exit $status

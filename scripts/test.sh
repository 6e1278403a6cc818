#!/usr/bin/env bash
# The whole test run, what .ci/run runs (README "Quick start", command 2):
#   1. set up and build (scripts/setup.sh), `luxloc --help`, the test suite (Release);
#   2. the test suite under ASan+UBSan (scripts/sanitize.sh asan, build-asan);
#   3. every fuzz target for LUXLOC_FUZZ_SECONDS each (default 20; scripts/fuzz.sh);
#   4. the threaded tests under TSan (scripts/sanitize.sh tsan, build-tsan).
# LUXLOC_QUICK=1 stops after step 1 (the Release suite only, ~2 minutes after the build).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
stamp() { echo "test.sh: $1 done after $(( $(date +%s) - start )) s"; }
bash scripts/setup.sh
build/luxloc --help >/dev/null
ctest --test-dir build --output-on-failure -j2
stamp "release suite"
[ "${LUXLOC_QUICK:-0}" = 1 ] && exit 0
bash scripts/sanitize.sh asan
stamp "ASan+UBSan suite"
bash scripts/fuzz.sh "${LUXLOC_FUZZ_SECONDS:-20}"
stamp "fuzzing"
bash scripts/sanitize.sh tsan
stamp "TSan suite"

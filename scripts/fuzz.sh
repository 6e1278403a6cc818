#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz) for SECONDS each (default 20) from its seed
# corpus, in the ASan+UBSan build of scripts/sanitize.sh (build-asan). Usage:
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh 0 fuzz_witmotion   # a fixed number of executions
# New inputs go to build-asan/fuzz-corpus/TARGET (the committed seeds stay as they are); a
# crash, a leak, a sanitizer report, a hang (> 10 s) or > 2 GB RSS stops with exit 1 and
# leaves the input as build-asan/fuzz-findings/TARGET/crash-* (docs/RELIABILITY.md).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-20}
shift || true
bash scripts/sanitize.sh asan --build-only
TARGETS=("$@")
if [ ${#TARGETS[@]} -eq 0 ]; then
  TARGETS=($(sed -n 's/^  \(fuzz_[a-z_0-9]*\).*/\1/p' tests/fuzz/CMakeLists.txt))
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
# The file-based targets write their input to a scratch folder each execution: on tmpfs
# (/dev/shm) that costs no disk I/O (fuzz_session_csv: 185 -> ~1300 executions a second).
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
for t in "${TARGETS[@]}"; do
  work=build-asan/fuzz-corpus/$t findings=build-asan/fuzz-findings/$t
  mkdir -p "$work" "$findings"
  limit=(-max_total_time="$SECONDS_EACH")
  if [ -n "${FUZZ_RUNS:-}" ]; then limit=(-runs="$FUZZ_RUNS"); fi
  log=build-asan/fuzz-findings/$t.log
  # A fixed seed (FUZZ_SEED, default 1): CI explores the same inputs every time; set another
  # seed for a new local campaign.
  if build-asan/tests/fuzz/$t "${limit[@]}" -seed="${FUZZ_SEED:-1}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
       -artifact_prefix="$findings/" "$work" "tests/fuzz/corpus/$t" >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz: $t: ok, $execs executions"
  else
    echo "fuzz: $t: FAILED (log: $log)"; tail -40 "$log"; status=1
  fi
done
exit $status

#!/usr/bin/env bash
# Idle cost of a live run: `luxloc run --source serial-imu:PTY` on a socat pty whose other
# end sends nothing, for S seconds (default 10); prints user + sys CPU (/usr/bin/time).
# Usage: bash scripts/bench_idle.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
SECS=${1:-10}
BIN=${LUXLOC_BIN:-build/luxloc}
dir=$(mktemp -d)
socat PTY,link="$dir/imu",raw,echo=0 EXEC:"sleep $((SECS + 5))" & sp=$!
trap 'kill $sp 2>/dev/null || true; rm -rf "$dir"' EXIT
for _ in $(seq 50); do [ -e "$dir/imu" ] && break; sleep 0.1; done
/usr/bin/time -f "bench idle: ${SECS} s of a silent serial IMU: user %U s, sys %S s (wall %e s, max RSS %M KB)" \
  timeout -s INT "$SECS" "$BIN" run --source "serial-imu:$dir/imu" -q --out /dev/null 2>&1 | grep "bench idle" || true

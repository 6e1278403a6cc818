#!/usr/bin/env bash
# Issue 16 part 5: ATE RMSE on the drone scenario (hold-out seeds 101-110): `run` defaults,
# the per-epoch least-squares multilateration of the same ranges (`run --uwb-alone`), each
# before and after `calib uwb` (calibrated from the session's own ground truth).
# Usage: scripts/bench_drone.sh [BUILD_DIR] [SCENARIO]
set -euo pipefail
B=${1:-build}; SC=${2:-drone}
W=$(mktemp -d /tmp/bench_drone.XXXXXX); trap 'rm -rf "$W"' EXIT
ate() { "$B/luxloc" eval "$1" --truth "$2/groundtruth.csv" --json | grep -o '"ate_rmse_m":[0-9.]*' | cut -d: -f2; }
printf "seed  run  lsq  run+calib  lsq+calib\n"
for s in $(seq 101 110); do
  d="$W/$s"; "$B/luxloc" sim --scenario "$SC" --seed "$s" --out "$d" >/dev/null
  "$B/luxloc" run --playback "$d" --out "$d/run.csv" >/dev/null 2>&1
  "$B/luxloc" run --playback "$d" --uwb-alone --out "$d/lsq.csv" >/dev/null 2>&1
  "$B/luxloc" calib uwb "$d" --out "$d/session.cal.yaml" >/dev/null && mv "$d/session.cal.yaml" "$d/session.yaml"
  "$B/luxloc" run --playback "$d" --out "$d/runc.csv" >/dev/null 2>&1
  "$B/luxloc" run --playback "$d" --uwb-alone --out "$d/lsqc.csv" >/dev/null 2>&1
  printf "%s  %s  %s  %s  %s\n" "$s" "$(ate "$d/run.csv" "$d")" "$(ate "$d/lsq.csv" "$d")" "$(ate "$d/runc.csv" "$d")" "$(ate "$d/lsqc.csv" "$d")"
done | tee "$W/table"
awk 'NR>0 {for (i=2;i<=5;i++) s[i]+=$i; n++} END {printf "mean  %.3f  %.3f  %.3f  %.3f\n", s[2]/n, s[3]/n, s[4]/n, s[5]/n}' "$W/table"

#!/usr/bin/env bash
# Issue 16: ATE RMSE on the drone / robot scenario (hold-out seeds 101-110 unless SEEDS says
# otherwise; tune on SEEDS="$(seq 1 10)"): `run` defaults (online height and per-anchor bias),
# its z RMSE and sigma consistency (share of poses within 2.45 sigma), the per-epoch
# least-squares multilateration of the same ranges (`run --uwb-alone`, the plain baseline),
# and both after `calib uwb` (calibrated from the session's own ground truth).
# Usage: [SEEDS="..."] [RUN_ARGS="..."] [SIM_ARGS="..."] [CALIB_ARGS="..."] scripts/bench_drone.sh [BUILD_DIR] [SCENARIO]
# (SIM_ARGS="--uwb-scale 0.01" CALIB_ARGS=--scale: anchors with range scale errors too)
set -euo pipefail
B=${1:-build}; SC=${2:-drone}
SEEDS=${SEEDS:-$(seq 101 110)}
RUN_ARGS=${RUN_ARGS:-}; SIM_ARGS=${SIM_ARGS:-}; CALIB_ARGS=${CALIB_ARGS:-}
W=$(mktemp -d /tmp/bench_drone.XXXXXX); trap 'rm -rf "$W"' EXIT
field() { "$B/luxloc" eval "$1" --truth "$2/groundtruth.csv" --json | grep -o "\"$3\":[0-9.]*" | cut -d: -f2; }
printf "seed  run  z  in2.45  lsq  run+calib  lsq+calib\n"
for s in $SEEDS; do
  # shellcheck disable=SC2086
  d="$W/$s"; "$B/luxloc" sim --scenario "$SC" --seed "$s" --out "$d" $SIM_ARGS >/dev/null
  # shellcheck disable=SC2086
  "$B/luxloc" run --playback "$d" --out "$d/run.csv" $RUN_ARGS >/dev/null 2>&1
  "$B/luxloc" run --playback "$d" --uwb-alone --out "$d/lsq.csv" >/dev/null 2>&1
  # shellcheck disable=SC2086
  "$B/luxloc" calib uwb "$d" --out "$d/session.cal.yaml" $CALIB_ARGS >/dev/null && mv "$d/session.cal.yaml" "$d/session.yaml"
  # shellcheck disable=SC2086
  "$B/luxloc" run --playback "$d" --out "$d/runc.csv" $RUN_ARGS >/dev/null 2>&1
  "$B/luxloc" run --playback "$d" --uwb-alone --out "$d/lsqc.csv" >/dev/null 2>&1
  printf "%s  %s  %s  %s  %s  %s  %s\n" "$s" "$(field "$d/run.csv" "$d" ate_rmse_m)" "$(field "$d/run.csv" "$d" z_rmse_m)" \
    "$(field "$d/run.csv" "$d" consistency)" "$(field "$d/lsq.csv" "$d" ate_rmse_m)" \
    "$(field "$d/runc.csv" "$d" ate_rmse_m)" "$(field "$d/lsqc.csv" "$d" ate_rmse_m)"
done | tee "$W/table"
awk '{for (i=2;i<=7;i++) s[i]+=$i; n++} END {printf "mean  %.3f  %.3f  %.3f  %.3f  %.3f  %.3f\n", s[2]/n, s[3]/n, s[4]/n, s[5]/n, s[6]/n, s[7]/n}' "$W/table"

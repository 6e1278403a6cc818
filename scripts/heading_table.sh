#!/usr/bin/env bash
# Fused heading of `luxloc run` (IMU + VLC) over the simulator's IMU grades and fields
# (docs/MOTION.md "Heading"). Usage: scripts/heading_table.sh [FIRST_SEED LAST_SEED [LUXLOC]];
# defaults: the hold-out seeds 101-110 (the heading state was tuned on 1-10). Per case, the
# mean over sessions of each session's yaw |error| p50 / p95, the worst p95 and max, the share
# of poses within 1.96 sigma_yaw, the ATE RMSE and the largest position error; each case with
# the heading state (default) and without it (--no-heading-state: the AHRS yaw, as before).
# Extra arguments after LUXLOC go to `luxloc run`. CASES selects cases by name, MODES (on, off) the rows.
set -euo pipefail
first=${1:-101}; last=${2:-110}; luxloc=${3:-build/luxloc}; shift $(( $# < 3 ? $# : 3 )) || true
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
declare -A sim_args=(
  [consumer]="--imu-grade consumer"
  [consumer-disturbed]="--imu-grade consumer --mag-disturbance both"
  [poor]="--imu-grade poor"
  [bias1-blackout]="--imu-grade consumer --gyro-bias-dps 0.3,-0.4,1.0 --mag-disturbance both --blackout 40:15"
)
printf '| case | heading state | sessions | yaw p50 | yaw p95 | worst p95 | yaw max | within 1.96 sigma_yaw | ATE RMSE | max error |\n|---|---|---|---|---|---|---|---|---|---|\n'
for case in ${CASES:-consumer consumer-disturbed poor bias1-blackout}; do
  for mode in ${MODES:-on off}; do
    : > "$tmp/rows"
    for seed in $(seq "$first" "$last"); do
      d="$tmp/s$seed"
      [[ -d "$d" ]] || "$luxloc" sim --out "$d" --scenario walk --seed "$seed" ${sim_args[$case]} > /dev/null 2>&1
      extra=(); [[ $mode == off ]] && extra=(--no-heading-state)
      "$luxloc" run --playback "$d" --out "$tmp/p.csv" -q "${extra[@]}" "$@"
      "$luxloc" eval "$tmp/p.csv" --truth "$d/groundtruth.csv" --json > "$tmp/e.json"
      python3 - "$tmp/e.json" >> "$tmp/rows" <<'PY'
import json, math, sys
e = json.load(open(sys.argv[1]))
d = lambda k: math.degrees(e[k])
print(d("yaw_p50_rad"), d("yaw_p95_rad"), d("yaw_max_rad"), e.get("yaw_consistency", float("nan")), e["ate_rmse_m"], e["max_m"])
PY
    done
    rm -rf "$tmp"/s*/.done
    awk -v c="$case" -v m="$mode" '{ p50 += $1; p95 += $2; if ($2 > w) w = $2; if ($3 > mx) mx = $3; cons += $4; ate += $5; if ($6 > me) me = $6; n++ }
      END { printf "| %s | %s | %d | %.2f deg | %.2f deg | %.2f deg | %.2f deg | %s | %.3f m | %.3f m |\n", c, m, n, p50/n, p95/n, w, mx,
            (m == "on" ? sprintf("%.1f %%", 100 * cons / n) : "-"), ate/n, me }' "$tmp/rows"
  done
  rm -rf "$tmp"/s*
done

#!/usr/bin/env bash
# Yaw error of `luxloc imu` over the simulator's IMU grades (docs/IMU.md "Heading under real
# MEMS gyros"). Usage: scripts/yaw_table.sh [FIRST_SEED LAST_SEED [LUXLOC]]; defaults: the
# hold-out seeds 101-120 (the filter was tuned on 1-10), build/luxloc. Per grade and field:
# the mean over sessions of each session's p50 and p95 of |yaw error|, the worst session's
# p95 and the largest error of all. Extra arguments after LUXLOC go to `luxloc imu`;
# LUXLOC_SIM names the binary that simulates (default build/luxloc), GRADES the grades,
# FIELDS the magnetic fields (default: none both; also steel, magnet).
set -euo pipefail
first=${1:-101}; last=${2:-120}; luxloc=${3:-build/luxloc}; shift $(( $# < 3 ? $# : 3 )) || true
sim=${LUXLOC_SIM:-build/luxloc}  # the simulator (LUXLOC may be an older build without the grades)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '| grade | field | sessions | yaw p50 (mean) | yaw p95 (mean) | worst p95 | max | mag rejected (mean %%) |\n|---|---|---|---|---|---|---|---|\n'
for grade in ${GRADES:-ideal tactical default consumer poor}; do
  for field in ${FIELDS:-none both}; do
    : > "$tmp/rows"
    for seed in $(seq "$first" "$last"); do
      d="$tmp/s"; rm -rf "$d"
      "$sim" sim --out "$d" --scenario walk --duration 90 --no-frames --seed "$seed" --imu-grade "$grade" \
        --mag-disturbance "$field" > /dev/null
      "$luxloc" imu --in "$d" --out "$tmp/att.csv" --truth "$d/groundtruth.csv" "$@" > "$tmp/out" 2>&1
      p=$(sed -n 's/.*yaw error p50 \([0-9.]*\) deg, p95 \([0-9.]*\) deg, max \([0-9.]*\) deg.*/\1 \2 \3/p' "$tmp/out")
      m=$(sed -n 's/.*, \([0-9]*\) magnetometer samples rejected.*/\1/p' "$tmp/out")
      echo "$p ${m:-0}" >> "$tmp/rows"
    done
    awk -v g="$grade" -v f="$field" '{ s50 += $1; s95 += $2; if ($2 > w95) w95 = $2; if ($3 > mx) mx = $3; rej += $4; n++ }
      END { printf "| %s | %s | %d | %.2f | %.2f | %.2f | %.2f | %.1f |\n", g, (f == "none" ? "clean" : (f == "both" ? "steel + magnet" : f)), n, s50/n, s95/n, w95, mx, 100 * rej / n / 9000 }' "$tmp/rows"
  done
done

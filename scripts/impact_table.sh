#!/usr/bin/env bash
# Heel-strike impacts and the step length (issue 12: "fast walking (1.7 m/s, 12 g peaks) keeps
# its step length"; core/imu/impact_filter.hpp). Each seed walks the fast walker (`luxloc sim
# --walker fast`, 1.7 m/s, 90 s, consumer IMU) twice: without impacts and with 12 g heel
# strikes (`--heel-impact 11`). `luxloc imu --truth` then counts the steps and sums the
# Weinberg step lengths (uncalibrated: only their ratio matters here). Per case, over the
# sessions: steps found and false (% of the true steps), and the PDR distance against the
# same walk without impacts (mean and worst |ratio - 1|). Usage:
#   scripts/impact_table.sh [FIRST LAST [LUXLOC]]   (defaults: hold-out seeds 101-110)
set -euo pipefail
first=${1:-101}; last=${2:-110}; luxloc=${3:-build/luxloc}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
: > "$tmp/rows"
for seed in $(seq "$first" "$last"); do
  for g in 0 11; do
    "$luxloc" sim --out "$tmp/g$g" --walker fast --heel-impact "$g" --imu-grade consumer --seed "$seed" --no-frames > /dev/null
  done
  for run in "0 on" "11 on" "11 off"; do
    set -- $run
    extra=(); [[ $2 == off ]] && extra=(--no-impact-filter)
    out=$("$luxloc" imu --in "$tmp/g$1" --out /dev/null --truth "$tmp/g$1/groundtruth.csv" "${extra[@]}" 2>&1)
    dist=$(sed -n 's/^pdr: [0-9]* steps, \([0-9.]*\) m walked.*/\1/p' <<< "$out")
    read -r found total false < <(sed -n 's/^truth: \([0-9]*\) of \([0-9]*\) steps found.*, \([0-9]*\) false.*/\1 \2 \3/p' <<< "$out")
    echo "$seed $1 $2 $dist $found $total $false" >> "$tmp/rows"
  done
done
printf '| heel strikes | impact filter | sessions | steps found | false steps | PDR distance / same walk without impacts: mean | worst |\n|---|---|---|---|---|---|---|\n'
awk '{ key = $2 " " $3; if ($2 == 0) ref[$1] = $4; d[key, $1] = $4; f[key] += $5; t[key] += $6; x[key] += $7; n[key]++; seeds[$1] = 1 }
  END {
    split("0 on|11 on|11 off", keys, "|")
    for (i = 1; i <= 3; i++) {
      k = keys[i]; split(k, kk, " "); s = 0; w = -1; m = 0
      for (sd in seeds) { r = d[k, sd] / ref[sd]; s += r; m++; e = r > 1 ? r - 1 : 1 - r; if (e > w) { w = e; ws = r } }
      printf "| %s | %s | %d | %.1f %% | %.1f %% | %.3f | %.3f |\n", (kk[1] == 0 ? "none" : "12 g"), kk[2], n[k],
             100 * f[k] / t[k], 100 * x[k] / t[k], s / m, ws
    }
  }' "$tmp/rows"

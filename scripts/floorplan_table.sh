#!/usr/bin/env bash
# Building-scale VLC with frequency reuse (issue 14): the floorplan scenario (60 m x 30 m,
# 450 LEDs in 12 frequency classes), 10-minute walks, one row per seed and case, then the
# worst of each column. Usage: scripts/floorplan_table.sh [FIRST LAST [LUXLOC]]; defaults:
# the hold-out seeds 201-206 (the constants of the global search were chosen on seeds 1 and
# 101). Every session draws its own walker (--walker random) and a consumer-grade IMU.
#   known    the true start pose given (--start): ATE RMSE over the whole walk
#   noprior  no start: settling time below 0.2 m (the walk starts after 0-2 s standing),
#            ATE RMSE after it, wrong copies while tracking (run --check-associations)
#   kidnap   no start, and at 300 s (or half the walk) carried 20 m with the camera covered (sim --kidnap):
#            recovery = settling below 0.2 m after the camera sees again, wrong copies
# DURATION (default 600) shortens the walks.
set -euo pipefail
first=${1:-201}; last=${2:-206}; luxloc=${3:-build/luxloc}
dur=${DURATION:-600}
kidnap_at=$(( dur / 2 < 300 ? dur / 2 : 300 ))
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '| seed | known: ATE RMSE | no prior: settled after | ATE after | wrong copies | kidnap: recovered after | wrong copies | searches |\n|---|---|---|---|---|---|---|---|\n'
: > "$tmp/rows"
for seed in $(seq "$first" "$last"); do
  args=(--scenario floorplan --seed "$seed" --walker random --imu-grade consumer --duration "$dur")
  rm -rf "$tmp/s"; "$luxloc" sim --out "$tmp/s" "${args[@]}" > /dev/null
  start=$(awk -F, 'NR==2 { print $2 "," $3 "," $5 }' "$tmp/s/groundtruth.csv")
  "$luxloc" run --playback "$tmp/s" --out "$tmp/known.csv" -q --start "$start" --start-sigma 0.05
  known=$("$luxloc" eval "$tmp/known.csv" --truth "$tmp/s/groundtruth.csv" --json)
  "$luxloc" run --playback "$tmp/s" --out "$tmp/free.csv" --check-associations > "$tmp/free.log" 2>&1
  free=$("$luxloc" eval "$tmp/free.csv" --truth "$tmp/s/groundtruth.csv" --settle 0.2 --json)
  settled=$(python3 -c 'import json,sys; j=json.loads(sys.argv[1]); print(j["settled_t"] if j["settled_t"] is not None else "nan")' "$free")
  after=$("$luxloc" eval "$tmp/free.csv" --truth "$tmp/s/groundtruth.csv" --from "${settled/nan/0}" --json)
  rm -rf "$tmp/s"; "$luxloc" sim --out "$tmp/s" "${args[@]}" --kidnap "$kidnap_at:20" > /dev/null
  back=$(awk '/^kidnap:/ { k = 1 } k && /end_s:/ { print $2; exit }' "$tmp/s/sim_truth.yaml")
  "$luxloc" run --playback "$tmp/s" --out "$tmp/kid.csv" --check-associations > "$tmp/kid.log" 2>&1
  kid=$("$luxloc" eval "$tmp/kid.csv" --truth "$tmp/s/groundtruth.csv" --from "$back" --settle 0.2 --json)
  python3 - "$seed" "$known" "$free" "$after" "$tmp/free.log" "$kid" "$tmp/kid.log" >> "$tmp/rows" <<'PY'
import json, re, sys
seed, known, free, after, flog, kid, klog = sys.argv[1:]
known, free, after, kid = map(json.loads, (known, free, after, kid))
def wrong(log):
    m = re.search(r"wrong copy (\d+) in (\d+) frames", open(log).read())
    return f"{m.group(1)} blobs / {m.group(2)} frames" if m else "?"
def searches(log):
    m = re.search(r"(\d+) global starts, (\d+) global restarts", open(log).read())
    return f"{m.group(1)} + {m.group(2)}" if m else "?"
f = lambda v, fmt: "never" if v is None else fmt % v
print(f"| {seed} | {known['ate_rmse_m']:.3f} m | {f(free['settled_t'], '%.1f s')} | {after['ate_rmse_m']:.3f} m | "
      f"{wrong(flog)} | {f(kid['settled_after_s'], '%.1f s')} | {wrong(klog)} | {searches(klog)} |")
PY
  tail -1 "$tmp/rows"
done

#!/usr/bin/env bash
# Issue 16 part 3: the drone under the LED ceiling (sim --scenario drone --camera), height
# from the camera geometry on / off, camera alone (uwb.csv left out) and camera + UWB.
# Hold-out seeds 101-110 unless SEEDS says otherwise (tuning: SEEDS="$(seq 1 5)").
# Prints per case the mean ATE RMSE, the worst session's, the share of poses within their
# 95 % ellipse (min-max over the sessions), z RMSE and the share within 1.96 sigma_z.
# Usage: [SEEDS="..."] scripts/camera_height_table.sh [BUILD_DIR]
set -euo pipefail
B=${1:-build}
SEEDS=${SEEDS:-$(seq 101 110)}
W=$(mktemp -d /tmp/camera_height.XXXXXX); trap 'rm -rf "$W"' EXIT
row() {  # seed case poses truth
  "$B/luxloc" eval "$3" --truth "$4" --json |
    python3 -c "import json,sys; j=json.load(sys.stdin); print('$1', '$2', *('%.4f' % j[k] for k in ('ate_rmse_m','consistency','z_rmse_m','z_consistency')))"
}
for s in $SEEDS; do
  d="$W/$s"; "$B/luxloc" sim --scenario drone --camera --seed "$s" --out "$d" >/dev/null
  v="$W/$s-cam"; mkdir -p "$v"; for f in "$d"/*; do ln -s "$f" "$v/"; done; rm "$v/uwb.csv"
  for c in "camera:$v:off" "camera:$v:on" "camera+uwb:$d:off" "camera+uwb:$d:on"; do
    IFS=: read -r name dir mode <<<"$c"
    "$B/luxloc" run --playback "$dir" --platform drone --camera-height "$mode" --out "$W/p.csv" >/dev/null 2>&1
    row "$s" "$name/height-$mode" "$W/p.csv" "$d/groundtruth.csv"
  done
  rm -rf "$d/frames"
done >"$W/rows"
printf "%-24s %9s %9s %13s %9s %13s\n" case "ATE mean" "ATE max" "in 95 % ell." "z RMSE" "in 1.96 sz"
python3 - "$W/rows" <<'PY'
import sys, collections
rows = collections.defaultdict(list)
for line in open(sys.argv[1]):
    s, case, ate, cons, z, zc = line.split()
    rows[case].append((float(ate), float(cons), float(z), float(zc)))
for case, v in rows.items():
    ate = [x[0] for x in v]; cons = [x[1] for x in v]; z = [x[2] for x in v]; zc = [x[3] for x in v]
    print("%-24s %9.3f %9.3f %6.1f-%5.1f %9.3f %6.1f-%5.1f" % (case, sum(ate)/len(ate), max(ate), 100*min(cons), 100*max(cons),
          sum(z)/len(z), 100*min(zc), 100*max(zc)))
PY

#!/usr/bin/env bash
# N luxloc runs (default 10) publish at once to one mosquitto broker on this machine, each
# a real-time sim: run at the default 50 Hz output for S seconds (default 20); one
# mosquitto_sub counts what arrives per device and checks the sequence numbers.
# Usage: bash scripts/bench_mqtt_fleet.sh [N] [SECONDS]   (prints one line per run, then a total)
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-10}; SECS=${2:-20}
BIN=${LUXLOC_BIN:-build/luxloc}
dir=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$dir"' EXIT
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\n' "$port" > "$dir/mosquitto.conf"
mosquitto -c "$dir/mosquitto.conf" 2>"$dir/broker.log" & broker=$!
for i in $(seq 50); do (exec 3<>/dev/tcp/127.0.0.1/$port) 2>/dev/null && break; sleep 0.1; done
mosquitto_sub -p "$port" -t 'luxloc/+/pose' -v > "$dir/received.txt" & sub=$!
sleep 0.5
pids=()
for i in $(seq "$N"); do
  "$BIN" run --source "sim:walk,duration=$SECS,seed=$i" --out /dev/null --device-id "bench$i" \
      --mqtt "127.0.0.1:$port" 2>"$dir/run$i.log" & pids+=($!)
done
for p in "${pids[@]}"; do wait "$p"; done
sleep 1
kill "$sub" "$broker" 2>/dev/null || true
wait 2>/dev/null || true
python3 - "$dir" "$N" <<'PY'
import json, re, sys
d, n = sys.argv[1], int(sys.argv[2])
got = {}
for line in open(f"{d}/received.txt"):
    topic, _, payload = line.partition(" ")
    got.setdefault(topic.split("/")[1], []).append(int(json.loads(payload)["seq"]))
total_sent = total_got = lost = 0
for i in range(1, n + 1):
    dev = f"bench{i}"
    sent = int(re.search(r"(\d+) poses over", open(f"{d}/run{i}.log").read()).group(1))
    seqs = got.get(dev, [])
    in_order = seqs == list(range(len(seqs)))
    total_sent += sent; total_got += len(seqs); lost += sent - len(seqs)
    print(f"  {dev}: {sent} poses computed, {len(seqs)} received, seq {'0..%d in order' % (len(seqs) - 1) if in_order else 'GAPS/REORDERED'}")
print(f"bench mqtt fleet: {n} runs, {total_sent} poses computed, {total_got} received, {lost} lost")
sys.exit(0 if lost == 0 else 1)
PY

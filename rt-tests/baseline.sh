#!/usr/bin/env bash
# Measures procimg's cycle timing beside its limits, on this machine, in one run:
#   - wake-up latency: the real cyclictest (rt-tests) and procimg-cyclictest, alternately;
#   - procimgd --demo with the synchronous example (plc_loop) running N cycles: the server's
#     wake-up latency, the STARTOP→OPDONE round trip, OPDONE in time, heap allocations.
# Prints one table. Needs root for SCHED_FIFO; build first: cargo build --release --bins --examples
#   rt-tests/baseline.sh [CYCLES] [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
cycles=${1:-10000}
rounds=${2:-2}
bin=target/release
command -v cyclictest >/dev/null || { echo "cyclictest missing: apt-get install rt-tests"; exit 1; }
for b in procimgd procimg procimg-cyclictest examples/plc_loop; do
    [ -x "$bin/$b" ] || { echo "$bin/$b missing: cargo build --release --bins --examples"; exit 1; }
done
instance="baseline-$$"
server_pid=""
trap '[ -n "$server_pid" ] && kill -INT "$server_pid" 2>/dev/null; wait 2>/dev/null || true' EXIT

# "T: 0 (tid) P:80 I:1000 C: n Min: a Act: b Avg: c Max: d" -> "a c d"
ct_fields() { sed -E 's/.*Min: *([0-9]+).*Avg: *([0-9]+).*Max: *([0-9]+).*/\1 \2 \3/'; }

printf 'machine: %s, %s CPUs, kernel %s\n' "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)" "$(nproc)" "$(uname -r)"
printf 'settings: SCHED_FIFO 80, 1000 µs interval, mlockall, %s cycles per run, %s rounds\n\n' "$cycles" "$rounds"
printf '%-7s %-40s %8s %8s %8s %8s %8s\n' round measurement min avg p99 p99.9 max
for r in $(seq "$rounds"); do
    read -r mn av mx < <(cyclictest -m -p 80 -i 1000 -l "$cycles" -q 2>/dev/null | tail -1 | ct_fields)
    printf '%-7s %-40s %8s %8s %8s %8s %8s\n' "$r" "cyclictest wake-up (µs)" "$mn" "$av" - - "$mx"
    read -r mn av mx < <("$bin/procimg-cyclictest" -m -p 80 -i 1000 -l "$cycles" -q 2>/dev/null | ct_fields)
    printf '%-7s %-40s %8s %8s %8s %8s %8s\n' "$r" "procimg-cyclictest wake-up (µs)" "$mn" "$av" - - "$mx"

    "$bin/procimgd" --demo --quiet --instance "$instance" 2>/dev/null &
    server_pid=$!
    for _ in $(seq 50); do "$bin/procimg" status -i "$instance" >/dev/null 2>&1 && break; sleep 0.1; done
    loop=$("$bin/examples/plc_loop" --instance "$instance" --cycles "$cycles" --min-in-time 0 2>/dev/null | head -1)
    "$bin/procimg" status -i "$instance" --json > /tmp/baseline-status.$$.json
    kill -INT "$server_pid"; wait "$server_pid" || true; server_pid=""
    python3 - "$r" "$loop" /tmp/baseline-status.$$.json <<'PY'
import json, sys
r, loop, path = sys.argv[1], sys.argv[2], sys.argv[3]
s = json.load(open(path))
def row(name, p):
    us = lambda ns: f"{ns/1000:.1f}"
    print(f"{r:<7} {name:<40} {us(p['min_ns']):>8} {us(p['mean_ns']):>8} {us(p['p99_ns']):>8} {us(p['p999_ns']):>8} {us(p['max_ns']):>8}")
row("procimgd cycle wake-up (µs)", s["wakeup_latency"])
row("procimgd STARTOP→OPDONE (µs)", s["handshake_round_trip"])
in_time = loop.split("OPDONE in time ")[1].split(" %")[0] if "OPDONE in time" in loop else "?"
print(f"{r:<7} {'plc_loop OPDONE in time (%)':<40} {in_time:>8}   ({s['overruns']} overruns, {s['rt_heap_allocations']} heap allocations on the cycle thread: iceoryx2 connection set-up when the client attached)")
PY
done
rm -f /tmp/baseline-status.$$.json

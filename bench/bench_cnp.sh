#!/usr/bin/env bash
# Contract Net negotiation over DDS with each contractor in its own process
# (`smartfactory agent machine`), 1/4/16/64 contractors: latency ANNOUNCE →
# confirmed AWARD (p50/p99, one at a time) and negotiations/s (8 in flight),
# each run next to Cyclone's ddsperf ping/pong round trip measured in the same
# run, as a ratio, and the CPU time of all processes per negotiation next to
# ddsperf's per round trip. In-process contractors: bench_cnp.
#
# Usage: bench/bench_cnp.sh [BUILD_DIR] [NEGOTIATIONS] [SPIN_US] [DELIVERY: inline|queued]
set -euo pipefail
build=${1:-build/release}
negotiations=${2:-500}
spin=${3:-0}
delivery=${4:-inline}
sf="$build/apps/smartfactory/smartfactory"
[ -x "$sf" ] || { echo "bench_cnp.sh: $sf not built" >&2; exit 1; }
command -v ddsperf >/dev/null || echo "bench_cnp.sh: ddsperf not found (cyclonedds-tools); no ratio" >&2

printf "contractor processes, %s negotiations per phase, executor spin %s us, %s delivery\n" "$negotiations" "$spin" \
  "$delivery"
printf "%11s %9s %9s %9s %15s %13s %12s %8s %12s %10s\n" contractors "p50 us" "p99 us" "mean us" \
  "one-at-a-time/s" "8-in-flight/s" "ddsperf us" "ratio" "CPU us/neg" "CPU ratio"
for n in 1 4 16 64; do
  json=$(SF_LOG=warn "$sf" cnp bench --contractors "$n" --negotiations "$negotiations" --processes \
           --spin-us "$spin" --delivery "$delivery" --json 2>/dev/null) || { echo "$n contractors: failed"; continue; }
  python3 - "$json" <<'PY'
import json, sys
d = json.loads(sys.argv[1])
l = d["latency_us"]
rtt = d["ddsperf_rtt_p50_us"]
ratio = d["ratio_p50"]
nan = float("nan")
cpu, cpu_ratio = d.get("cpu_us_per_negotiation"), d.get("cpu_ratio")
print(f"{d['contractors']:11d} {l['p50']:9.1f} {l['p99']:9.1f} {l['mean']:9.1f} {d['sequential_per_s']:15.0f} "
      f"{d['pipelined_per_s']:13.0f} {rtt if rtt is not None else nan:12.1f} "
      f"{ratio if ratio is not None else nan:7.1f}x {cpu if cpu is not None else nan:12.1f} "
      f"{cpu_ratio if cpu_ratio is not None else nan:9.1f}x")
PY
done

#!/usr/bin/env bash
# Contract Net negotiation over DDS with each contractor in its own process
# (`smartfactory agent machine`), 1/4/16/64 contractors: latency ANNOUNCE →
# confirmed AWARD (p50/p99, one at a time) and negotiations/s (8 in flight),
# each run next to Cyclone's ddsperf ping/pong round trip measured in the same
# run, as a ratio, and the CPU time of all processes per negotiation next to
# ddsperf's per round trip. In-process contractors: bench_cnp.
#
# The contractor processes and ddsperf's pongs run under SCHED_BATCH by default, so that the
# contractors a fan-out wakes do not preempt the product (or ping) in the middle of it; `normal`
# lets them (`smartfactory cnp bench --help`, docs/performance.md).
#
# ROUNDS > 1 repeats each fan-out (negotiations, then ddsperf, again and again) and adds a row
# with the median of each column over the rounds: on a shared machine one round's ratio moves
# with whatever else ran during it, the median of several much less.
#
# Usage: bench/bench_cnp.sh [BUILD_DIR] [NEGOTIATIONS] [SPIN_US] [DELIVERY: inline|queued]
#                           [CONTRACTOR_SCHED: batch|normal] [ROUNDS] [FAN_OUTS, e.g. "16 64"]
set -euo pipefail
build=${1:-build/release}
negotiations=${2:-500}
spin=${3:-0}
delivery=${4:-inline}
sched=${5:-batch}
rounds=${6:-1}
fan_outs=${7:-1 4 16 64}
sf="$build/apps/smartfactory/smartfactory"
[ -x "$sf" ] || { echo "bench_cnp.sh: $sf not built" >&2; exit 1; }
command -v ddsperf >/dev/null || echo "bench_cnp.sh: ddsperf not found (cyclonedds-tools); no ratio" >&2

printf "contractor processes (%s scheduling), %s negotiations per phase, executor spin %s us, %s delivery, %s round(s)\n" \
  "$sched" "$negotiations" "$spin" "$delivery" "$rounds"
printf "%11s %9s %9s %9s %15s %13s %12s %8s %12s %10s %12s %10s\n" contractors "p50 us" "p99 us" "mean us" \
  "one-at-a-time/s" "8-in-flight/s" "ddsperf p50" "ratio" "ddsperf mean" "mean ratio" "CPU us/neg" "CPU ratio"
row() {
  python3 - "$@" <<'PY'
import json, statistics, sys
runs = [json.loads(a) for a in sys.argv[1:]]
nan = float("nan")
def col(get):
    xs = [x for x in (get(d) for d in runs) if x is not None]
    return statistics.median(xs) if xs else nan
l = lambda k: col(lambda d: d["latency_us"][k])
v = lambda k: col(lambda d: d.get(k))
label = str(runs[0]["contractors"]) + ("" if len(runs) == 1 else " median")
print(f"{label:>11} {l('p50'):9.1f} {l('p99'):9.1f} {l('mean'):9.1f} {v('sequential_per_s'):15.0f} "
      f"{v('pipelined_per_s'):13.0f} {v('ddsperf_rtt_p50_us'):12.1f} {v('ratio_p50'):7.2f}x "
      f"{v('ddsperf_rtt_mean_us'):12.1f} {v('ratio_mean'):9.2f}x {v('cpu_us_per_negotiation'):12.1f} "
      f"{v('cpu_ratio'):9.2f}x")
PY
}
for n in $fan_outs; do
  results=()
  for ((r = 0; r < rounds; r++)); do
    json=$(SF_LOG=warn "$sf" cnp bench --contractors "$n" --negotiations "$negotiations" --processes \
             --spin-us "$spin" --delivery "$delivery" --contractor-sched "$sched" --json 2>/dev/null) \
      || { echo "$n contractors: failed"; continue; }
    row "$json"
    results+=("$json")
  done
  if [ "${#results[@]}" -gt 1 ]; then
    row "${results[@]}"
  fi
done

#!/usr/bin/env bash
# EtherCAT over a veth pair between two network namespaces (needs root):
#  - round trip and cycle jitter at 1 kHz and 4 kHz for 1, 8 and 64 slaves
#    (`ecat sim` in one namespace, `ecat run` in the other);
#  - frames per second the emulated segment sustains (cycle of 50 us);
# each next to the wire floor measured in the same run: ecat_echo_peer
# reflecting frames of the same size over the same veth pair.
# Usage: bench/ecat_veth.sh BUILD_DIR [SECONDS]
# Extra options for the master and the segment: ECAT_RUN_ARGS, ECAT_SIM_ARGS
# (e.g. ECAT_RUN_ARGS="--busy-poll-us 0" to measure a master that sleeps).
set -euo pipefail
build="${1:-build/release}"
secs="${2:-5}"
sf="$build/apps/smartfactory/smartfactory"
echo_peer="$build/bench/ecat_echo_peer"
if [ "$(id -u)" -ne 0 ]; then echo "ecat_veth: needs root for network namespaces; skipped"; exit 0; fi
tag=$$
nsm="sfbm$tag"; nss="sfbs$tag"; ifm="sfbvm$tag"; ifs="sfbvs$tag"
cleanup() { ip netns del "$nsm" 2>/dev/null || true; ip netns del "$nss" 2>/dev/null || true; }
trap cleanup EXIT
ip netns add "$nsm"; ip netns add "$nss"
ip link add "$ifm" type veth peer name "$ifs"
ip link set "$ifm" netns "$nsm"; ip link set "$ifs" netns "$nss"
ip -n "$nsm" link set "$ifm" up; ip -n "$nss" link set "$ifs" up
work=$(mktemp -d)

declare -A spec=([1]="smart-controller:1" [8]="smart-controller:1,digital-io:4,servo:3"
                 [64]="smart-controller:4,digital-io:40,servo:20")
field() { python3 -c "import json,sys; d=json.load(open('$1')); print(eval('d' + sys.argv[1]))" "$2"; }

printf "%-7s %-6s | %-34s | %-34s | %s\n" "slaves" "rate" "ecat run rtt us min/med/p99/max" \
  "echo rtt us min/med/p99/max" "median ratio; jitter us med/p99/max"
for n in 1 8 64; do
  for rate in 1000 4000; do
    cycle=$((1000000 / rate))
    ip netns exec "$nss" "$sf" ecat sim --iface "$ifs" --slaves "${spec[$n]}" ${ECAT_SIM_ARGS:-} >"$work/sim.log" 2>&1 &
    sim=$!
    sleep 0.5
    ip netns exec "$nsm" "$sf" ecat run --iface "$ifm" --cycle-us "$cycle" --duration "$secs" --json ${ECAT_RUN_ARGS:-} \
      >"$work/run.json" 2>"$work/run.log" || { cat "$work/run.log"; kill $sim; exit 1; }
    kill -TERM $sim; wait $sim || true
    size=$(field "$work/run.json" "['frame_bytes']")
    ip netns exec "$nss" "$echo_peer" serve "$ifs" & peer=$!
    sleep 0.3
    ip netns exec "$nsm" "$echo_peer" ping "$ifm" "$size" "$rate" "$secs" >"$work/echo.json"
    kill -TERM $peer; wait $peer || true
    r="['round_trip_us']"; j="['jitter_us']"
    printf "%-7s %-6s | %7.1f %7.1f %7.1f %8.1f   | %7.1f %7.1f %7.1f %8.1f   | x%.2f; %.1f/%.1f/%.1f (%s cycles, %s frame/cycle of %s B, lost %s)\n" \
      "$n" "${rate}Hz" \
      "$(field "$work/run.json" "$r['min']")" "$(field "$work/run.json" "$r['median']")" \
      "$(field "$work/run.json" "$r['p99']")" "$(field "$work/run.json" "$r['max']")" \
      "$(field "$work/echo.json" "$r['min']")" "$(field "$work/echo.json" "$r['median']")" \
      "$(field "$work/echo.json" "$r['p99']")" "$(field "$work/echo.json" "$r['max']")" \
      "$(python3 -c "print($(field "$work/run.json" "$r['median']") / max($(field "$work/echo.json" "$r['median']"), 0.001))")" \
      "$(field "$work/run.json" "$j['median']")" "$(field "$work/run.json" "$j['p99']")" "$(field "$work/run.json" "$j['max']")" \
      "$(field "$work/run.json" "['cycles']")" "$(field "$work/run.json" ".get('frames_per_cycle', '?')")" "$size" \
      "$(field "$work/run.json" "['lost_frames']")"
  done
done

echo
echo "frames per second, back to back (cycle 50 us) vs echo of the same frame size:"
for n in 1 8 64; do
  ip netns exec "$nss" "$sf" ecat sim --iface "$ifs" --slaves "${spec[$n]}" ${ECAT_SIM_ARGS:-} >"$work/sim.log" 2>&1 &
  sim=$!
  sleep 0.5
  ip netns exec "$nsm" "$sf" ecat run --iface "$ifm" --cycle-us 50 --duration "$secs" --json ${ECAT_RUN_ARGS:-} \
    >"$work/run.json" 2>/dev/null
  kill -TERM $sim; wait $sim || true
  size=$(field "$work/run.json" "['frame_bytes']")
  ip netns exec "$nss" "$echo_peer" serve "$ifs" & peer=$!
  sleep 0.3
  ip netns exec "$nsm" "$echo_peer" ping "$ifm" "$size" 0 "$secs" >"$work/echo.json"
  kill -TERM $peer; wait $peer || true
  ours=$(python3 -c "print($(field "$work/run.json" "['cycles']") / $secs)")
  theirs=$(field "$work/echo.json" "['frames_per_s']")
  printf "  %3s slaves: %9.0f frames/s  echo %9.0f frames/s  ratio %.2f\n" "$n" "$ours" "$theirs" \
    "$(python3 -c "print($ours / max($theirs, 1))")"
done
rm -rf "$work"

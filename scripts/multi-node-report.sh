#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One light shared by several vpe-player nodes through an MQTT broker
# (docs/multi-node.md), measured on this machine: three headless players at 60 Hz on a small
# bundle (160 × 90) and a mosquitto of the script's own on a free loopback port, with the
# password file, boards/mosquitto/acl and the board [bus] sections a gallery would use.
#   1. agreement: node-a (controller) replays knob turns, node-b and node-c (players) follow;
#      their --light-log files compared at equal presentation times.
#   2. faults: a node started before the broker, the broker killed and restarted while node-a
#      steers, a node killed and restarted, a node with the wrong password.
#   3. load: a controller (vpe_bus_load) publishing 1,000 states a second to the three nodes.
#   scripts/multi-node-report.sh [--out DIR] [--load-seconds 60]
# The last line of stdout is one JSON object:
#   agreement_p99_ms           for every frame of node-b and node-c, the time lag at which
#                              node-a's light (interpolated between its frames) is where theirs
#                              is (light_log_agreement.h); the 99th percentile over all frames
#   remote_latency_p50_frames  each time node-a starts moving after standing still (single
#                              knob detents 1.2 s apart), the first frame of node-b or node-c
#                              that moves, minus node-a's, in 60 Hz frames: the median
#   faults                     [{name, passed}] (what each needs is printed on stderr)
#   load_fps_min               the fewest frames a second any node presented during the load
#                              (ticks of its 60 Hz clock; a tick with no new state presents the
#                              frame again without drawing it)
#   load_rss_growth_kib        the most any node's VmRSS grew from 5 s into the load to its end
set -euo pipefail
cd "$(dirname "$0")/.."
out=multi-node-report load_seconds=60
source scripts/lib/report.sh
report_options multi-node-report out load-seconds -- "$@"
[[ "$load_seconds" =~ ^[0-9]+$ && "$load_seconds" -ge 10 ]] ||
    { echo "multi-node-report: --load-seconds: expected a whole number from 10, got '$load_seconds'" >&2; exit 2; }
start_report
mkdir -p "$out/broker"
cmake --build --preset release --target vpe_write_test_bundle vpe_bus_load vpe_light_log_compare \
    -j "$(nproc)" >&2
tools=$(realpath build/release/tests/firmware/bus)
now_us() { date +%s%6N; }
compare() { "$tools/vpe_light_log_compare" "$@"; }

# Everything this script starts, stopped by pid when it ends.
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill -KILL "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
}
trap cleanup EXIT

# A free TCP port on loopback: nothing answers there.
port=""
for _ in $(seq 50); do
    candidate=$((20000 + RANDOM % 40000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$candidate") 2>/dev/null; then port=$candidate; break; fi
done
[[ -n "$port" ]] || { echo "multi-node-report: no free port on 127.0.0.1" >&2; exit 1; }

"$tools/vpe_write_test_bundle" --out "$out/scene.vpeb" --size 160x90 >&2
bundle=$out/scene.vpeb

# The broker: no anonymous clients, the shipped ACL, retained states kept on disk.
: >"$out/broker/passwords"
mosquitto_passwd -b "$out/broker/passwords" vpe-controller controller-secret
mosquitto_passwd -b "$out/broker/passwords" vpe-player player-secret
{
    [[ $(id -u) -eq 0 ]] && echo "user root"  # as root mosquitto would switch to "mosquitto"
    echo "listener $port 127.0.0.1"
    echo "allow_anonymous false"
    echo "password_file $out/broker/passwords"
    echo "acl_file $(realpath boards/mosquitto/acl)"
    echo "persistence true"
    echo "persistence_location $out/broker/"
    echo "log_dest file $out/broker/mosquitto.log"
} >"$out/broker/mosquitto.conf"
broker_pid=""
start_broker() {
    /usr/sbin/mosquitto -c "$out/broker/mosquitto.conf" >>"$out/broker/mosquitto.out" 2>&1 &
    broker_pid=$!
    pids+=("$broker_pid")
    for _ in $(seq 500); do
        (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null && return 0
        sleep 0.01
    done
    echo "multi-node-report: mosquitto did not start: $(cat "$out/broker/mosquitto.out")" >&2
    exit 1
}
stop_broker() { kill "-$1" "$broker_pid"; wait "$broker_pid" 2>/dev/null || true; }

# board NAME USER ROLE [PASSWORD]: a headless node at 60 Hz, the replay's knobs (off: a replay
# decodes with them), no OSC, the bus.
board() {
    local user=$2 password=${4:-}
    [[ -n "$password" ]] || password=$([[ $user == vpe-controller ]] && echo controller-secret || echo player-secret)
    cat >"$out/$1.toml" <<EOF
[display]
backend = "headless"
[render]
rate = 60
[light]
azimuth = [-90, 90]
elevation = [0, 80]
distance = [0.05, 5]
initial_distance = 0.6
smoothing_s = 0.12
[idle]
enabled = true
quiet_s = 1.5
period_s = 8
handover_s = 1
[osc]
enabled = false
[bus]
host = "127.0.0.1"
port = $port
username = "$user"
password = "$password"
show = "report"
role = "$3"
client_id = "$1"
[gpio]
enabled = false
[[gpio.encoder]]
a = 17
b = 18
axis = "azimuth"
step = 2
[[gpio.encoder]]
a = 22
b = 23
axis = "elevation"
step = 1
EOF
}
# start NAME RUN [vpe-player arguments]: in the background, files $out/NAME-RUN.*
declare -A node_pid
start() {
    local name=$1 run=$2
    shift 2
    "$player" --board "$out/$name.toml" --bundle "$bundle" --light-log "$out/$name-$run.jsonl" \
        --json "$@" >"$out/$name-$run.out" 2>"$out/$name-$run.err" &
    node_pid[$name]=$!
    pids+=("$!")
}
stop() {  # stop NAME: SIGTERM and wait (in this shell: its child); the exit status in $status
    status=0
    kill -TERM "${node_pid[$1]}" 2>/dev/null || true
    wait "${node_pid[$1]}" || status=$?
}
wait_for() {  # wait_for FILE TEXT [SECONDS]
    for _ in $(seq $((${3:-5} * 100))); do
        grep -q "$2" "$1" 2>/dev/null && return 0
        sleep 0.01
    done
    echo "multi-node-report: $1: no '$2'" >&2
    return 1
}
count() { grep -c "$2" "$1" || true; }
first_us() { head -n 1 "$1" | sed 's/.*"t_us": \([0-9]*\).*/\1/'; }
last_us() { tail -n 1 "$1" | sed 's/.*"t_us": \([0-9]*\).*/\1/'; }

# Knob turns as GPIO edges (firmware/README.md, "Replay"): turn A B START DETENTS SPACING.
knob_replay() {
    awk -v script="$1" 'BEGIN {
        n = split(script, turns, ";")
        for (i = 1; i <= n; i++) {
            split(turns[i], f, " ")
            a = f[1]; b = f[2]; start = f[3]; detents = f[4]; spacing = f[5]
            count = detents < 0 ? -detents : detents
            for (k = 0; k < count; k++) {
                t = start + k * spacing
                first = detents > 0 ? a : b; second = detents > 0 ? b : a
                printf "{\"t\": %.4f, \"type\": \"gpio\", \"line\": %d, \"edge\": \"falling\"}\n", t, first
                printf "{\"t\": %.4f, \"type\": \"gpio\", \"line\": %d, \"edge\": \"falling\"}\n", t + 0.002, second
                printf "{\"t\": %.4f, \"type\": \"gpio\", \"line\": %d, \"edge\": \"rising\"}\n", t + 0.004, first
                printf "{\"t\": %.4f, \"type\": \"gpio\", \"line\": %d, \"edge\": \"rising\"}\n", t + 0.006, second
            }
        }
    }' | sort -t: -k2 -g
}

faults=()
fault() {  # fault NAME PASSED(0|1) WHY
    faults+=("{\"name\": \"$1\", \"passed\": $([[ $2 == 1 ]] && echo true || echo false)}")
    printf '   %-24s %s  %s\n' "$1" "$([[ $2 == 1 ]] && echo passed || echo FAILED)" "$3" >&2
}

step "1. agreement: node-a steered by replayed knob turns, node-b and node-c following"
start_broker
board node-a vpe-controller controller
board node-b vpe-player player
board node-c vpe-player player
start node-b 1
start node-c 1
wait_for "$out/node-b-1.err" "bus: connected to"
wait_for "$out/node-c-1.err" "bus: connected to"
# 12 single detents 1.2 s apart (the latency probes), then turns of both knobs, then quiet:
# the idle drift, drawn by every node from the shared clock.
probes=""
for k in $(seq 0 11); do
    probes+="17 18 $(awk -v k="$k" 'BEGIN { printf "%.2f", 0.5 + 1.2 * k }') $((k % 2 == 0 ? 1 : -1)) 0.05;"
done
knob_replay "${probes}17 18 15.0 12 0.04;22 23 15.6 10 0.03;17 18 16.2 -20 0.025;22 23 17.0 -6 0.08;17 18 17.8 8 0.1" \
    >"$out/knobs.jsonl"
start node-a 1 --replay "$out/knobs.jsonl" --frames 1380  # 23 s: the drift from ~20 s
wait "${node_pid[node-a]}" || { echo "multi-node-report: node-a failed: $(cat "$out/node-a-1.err")" >&2; exit 1; }
for name in node-b node-c; do
    stop "$name"
    [[ $status == 0 ]] || { echo "multi-node-report: $name failed: $(cat "$out/$name-1.err")" >&2; exit 1; }
done
from=$(($(first_us "$out/node-a-1.jsonl") + 300000))
to=$(($(last_us "$out/node-a-1.jsonl") - 300000))
compare agreement --reference "$out/node-a-1.jsonl" --from-us "$from" --to-us "$to" \
    "$out/node-b-1.jsonl" "$out/node-c-1.jsonl" >"$out/agreement.json"
compare latency --reference "$out/node-a-1.jsonl" --from-us "$from" --to-us "$to" \
    "$out/node-b-1.jsonl" "$out/node-c-1.jsonl" >"$out/latency.json"
echo "   agreement $(cat "$out/agreement.json")" >&2
echo "   latency   $(jq -c '{onsets, matched, p50_frames}' "$out/latency.json")" >&2
stop_broker TERM

step "2. faults"
rm -f "$out/broker/mosquitto.db"
board node-d vpe-player player wrong-password
# The broker absent when a node starts: one line, and it plays on; it connects when the broker comes.
start node-b 2
wait_for "$out/node-b-2.err" "cannot reach the broker"
sleep 0.5
start_broker
broker_started=$(now_us)
ok=1
wait_for "$out/node-b-2.err" "bus: connected to" || ok=0
[[ $(count "$out/node-b-2.err" "cannot reach the broker") == 1 ]] || ok=0
fault broker_absent_at_start "$ok" "one line, then connected by itself"
start node-c 2
start node-d 2
# node-a turns a knob every 0.2 s, over and over (--replay-loop).
turns=""
for k in $(seq 0 11); do
    turns+="17 18 $(awk -v k="$k" 'BEGIN { printf "%.2f", 0.2 + 0.25 * k }') $((k % 4 < 2 ? 2 : -2)) 0.03;"
done
knob_replay "$turns" >"$out/loop.jsonl"
start node-a 2 --replay "$out/loop.jsonl" --replay-loop
wait_for "$out/node-a-2.err" "bus: connected to"
wait_for "$out/node-c-2.err" "bus: connected to"
sleep 1.5
# The broker dies while node-a steers; it comes back 1.5 s later.
died=$(now_us)
stop_broker KILL
sleep 1.5
start_broker
back=$(now_us)
sleep 2.5
# A node dies and comes back: it takes the retained state.
kill -KILL "${node_pid[node-c]}"
wait "${node_pid[node-c]}" 2>/dev/null || true
sleep 0.5
start node-c 3
sleep 3
statuses=""
for name in node-a node-b node-c node-d; do
    stop "$name"
    statuses+="$status "
done

ok=1
why=""
outage=$(compare agreement --reference "$out/node-a-2.jsonl" --from-us $((died + 300000)) --to-us "$back" \
    "$out/node-b-2.jsonl" | jq .max_ms)
settled=$(compare settle --reference "$out/node-a-2.jsonl" --from-us "$back" --to-us $((back + 2000000)) \
    "$out/node-b-2.jsonl" "$out/node-c-2.jsonl")
jq -e '.settled_ms | all(. != null and . <= 1000)' <<<"$settled" >/dev/null || ok=0
awk -v m="$outage" 'BEGIN { exit !(m > 16.7) }' || { ok=0; why=" (the outage changed nothing?)"; }
fault broker_restart "$ok" "diverged during the outage (max lag $outage ms), agree again: $(jq -c .settled_ms <<<"$settled") ms after the broker's return$why"

ok=1
restart_from=$(first_us "$out/node-c-3.jsonl")
settled=$(compare settle --reference "$out/node-a-2.jsonl" --from-us "$restart_from" \
    --to-us $(($(last_us "$out/node-c-3.jsonl") - 200000)) "$out/node-c-3.jsonl")
jq -e '.settled_ms | all(. != null and . <= 1000)' <<<"$settled" >/dev/null || ok=0
fault node_restart "$ok" "agrees $(jq -c .settled_ms <<<"$settled") ms after its first frame"

ok=1
[[ $(count "$out/node-d-2.err" "refused the connection") == 1 ]] || ok=0
[[ $(jq '.counters["bus.connections"]' <(tail -n 1 "$out/node-d-2.out")) == 0 ]] || ok=0
fault wrong_credentials "$ok" "$(count "$out/node-d-2.err" "refused the connection") line, $(jq '.counters["bus.failed_attempts"]' <(tail -n 1 "$out/node-d-2.out")) attempts refused, never connected"

ok=1
gaps=$(compare gaps "$out/node-a-2.jsonl" "$out/node-b-2.jsonl" "$out/node-d-2.jsonl" "$out/node-c-3.jsonl" | jq .largest_gap_ms)
awk -v g="$gaps" 'BEGIN { exit !(g < 100) }' || ok=0
[[ "$statuses" == "0 0 0 0 " ]] || ok=0
fault nodes_kept_drawing "$ok" "largest gap between frames $gaps ms; exit statuses $statuses"
stop_broker TERM

step "3. load: 1,000 states a second for $load_seconds s"
for name in node-a node-b node-c; do board "$name" vpe-player player; done
start_broker
for name in node-a node-b node-c; do start "$name" 4; done
for name in node-a node-b node-c; do wait_for "$out/$name-4.err" "bus: connected to"; done
"$tools/vpe_bus_load" --port "$port" --user vpe-controller --password controller-secret \
    --show report --rate 1000 --seconds "$load_seconds" >"$out/load.json" 2>"$out/load.err" &
load_pid=$!
pids+=("$load_pid")
load_from=$(now_us)
sleep 5
declare -A rss_early
for name in node-a node-b node-c; do
    rss_early[$name]=$(awk '/^VmRSS/ { print $2 }' "/proc/${node_pid[$name]}/status")
done
wait "$load_pid" || { echo "multi-node-report: vpe_bus_load failed: $(cat "$out/load.err")" >&2; exit 1; }
load_to=$(now_us)
growth=0
fps_min=1000
for name in node-a node-b node-c; do
    rss_end=$(awk '/^VmRSS/ { print $2 }' "/proc/${node_pid[$name]}/status")
    grew=$((rss_end - rss_early[$name]))
    ((grew > growth)) && growth=$grew
    stop "$name"
    [[ $status == 0 ]] || { echo "multi-node-report: $name failed under load" >&2; exit 1; }
    # Frames a second from 1 s into the load to its end: every tick of the 60 Hz clock that
    # presented a frame. A tick whose light equals the last frame's (no new state arrived in
    # those 16.7 ms) presents it again without drawing; the drawn ones are shown beside.
    read -r fps drawn < <(awk -v a=$((load_from + 1000000)) -v b="$load_to" '
        { t = $2 + 0 } t >= a && t <= b { n++; if (/"drawn": true/) d++ }
        END { s = (b - a) / 1e6; printf "%.1f %.1f\n", n / s, d / s }' FS='"t_us": ' "$out/$name-4.jsonl")
    fps_min=$(awk -v a="$fps_min" -v b="$fps" 'BEGIN { print (b < a ? b : a) }')
    echo "   $name: $fps frames/s ($drawn drawn), VmRSS ${rss_early[$name]} → $rss_end KiB, received $(jq '.counters["bus.received"]' <(tail -n 1 "$out/$name-4.out")) states" >&2
done
echo "   load $(cat "$out/load.json")" >&2
stop_broker TERM

faults_json=$(IFS=,; echo "[${faults[*]}]")
jq -c -n --slurpfile agreement "$out/agreement.json" --slurpfile latency "$out/latency.json" \
    --argjson faults "$faults_json" --argjson fps "$fps_min" --argjson growth "$growth" \
    '{agreement_p99_ms: ($agreement[0].p99_ms * 100 | round / 100),
      remote_latency_p50_frames: ($latency[0].p50_frames * 100 | round / 100),
      faults: $faults, load_fps_min: $fps, load_rss_growth_kib: $growth}'

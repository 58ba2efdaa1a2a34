#!/usr/bin/env bash
# The window's frame rates (docs/benchmarks.md, "The window"): `kdray
# render SCENE --window --frames N --stats` under Xvfb (xvfb-run), whose
# `--stats` object on exit gives each kind of frame's count, time and
# longest frame:
#   - the seed scene in a 640x360 window, still: refining to its 16 samples
#     per pixel, then idle;
#   - the same while orbiting (KDRAY_AUTO_ORBIT=3: a drag of 3 pixels a
#     frame), 120 frames;
#   - 200,000 random spheres (a 20 MB TOML file) in a 320x240 window,
#     orbiting, 150 frames, alone and with the scene file touched once the
#     window is up, so that it reloads (on a worker thread) while orbiting.
# ROUNDS rounds (default 3), the cases alternating within each. Writes OUT
# (default docs/results/window.json) with the machine, its load and the
# commit, and prints the table scripts/window_table.py makes of it.
#
#   scripts/window_bench.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
# Needs xvfb-run (apt-get install xvfb xauth libxkbcommon-x11-0).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/window.json "$@"
rounds=${ROUNDS:-3}
command -v xvfb-run >/dev/null || { echo "window_bench.sh: no xvfb-run (apt-get install xvfb xauth)" >&2; exit 1; }
export XDG_RUNTIME_DIR=$work/xdg
mkdir -m 700 "$XDG_RUNTIME_DIR"
"$kdray" generate --kind spheres --count 200000 -o "$work/spheres-200k.toml" >/dev/null 2>&1

runs=()
# window NAME ORBIT TOUCH SCENE ARGS...: one window's --stats, tagged with
# the reloads it reported; TOUCH=1 touches SCENE a second after the window
# says it is up.
window() {
    local name=$1 orbit=$2 touch=$3 scene=$4
    shift 4
    : >"$work/stderr.txt"
    local orbiting=(-u KDRAY_AUTO_ORBIT)
    [ -z "$orbit" ] || orbiting=(KDRAY_AUTO_ORBIT="$orbit")
    env "${orbiting[@]}" xvfb-run -a -s "-screen 0 1024x768x24" \
        "$kdray" render "$scene" --window --stats "$@" >"$work/stats.json" 2>"$work/stderr.txt" &
    local pid=$!
    if [ "$touch" = 1 ]; then
        for _ in $(seq 600); do
            grep -q " window on " "$work/stderr.txt" && break
            sleep 0.1
        done
        sleep 1
        touch "$scene"
    fi
    wait "$pid"
    local reloads
    reloads=$(grep -c "^kdray: reloaded " "$work/stderr.txt" || true)
    runs+=("{\"case\": \"$name\", \"reloads\": $reloads, \"stats\": $(cat "$work/stats.json")}")
}
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    window "seed, still" "" 0 scenes/seed.toml --width 640 --height 360 --frames 60
    window "seed, orbiting" 3 0 scenes/seed.toml --width 640 --height 360 --frames 120
    window "200,000 spheres, orbiting" 3 0 "$work/spheres-200k.toml" --width 320 --height 240 --frames 150
    window "200,000 spheres, orbiting, reloaded" 3 1 "$work/spheres-200k.toml" --width 320 --height 240 \
        --frames 150
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/window_table.py "$out"

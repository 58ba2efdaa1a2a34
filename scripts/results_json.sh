# Sourced by the scripts that keep a measurement in docs/results: their
# arguments and temporary folder, the machine's and adapter's names, and
# the JSON files they write.

# The measuring scripts' `[KDRAY] [OUT]`: sets `kdray` (absolute; by
# default this checkout's release build, built first, since the figures
# name the checkout), `out` (default DEFAULT_OUT) and `work`, a temporary
# folder removed on exit (a script with more to clean up sets its own
# trap after this).
measure_setup() { # DEFAULT_OUT [KDRAY] [OUT]
    out=${3:-$1}
    kdray=$(realpath "${2:-target/release/kdray}")
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
    if [ $# -lt 2 ]; then
        cargo build --release --locked -q
    fi
}

# Copies kdray bench's BENCH_JSON to OUT with the checkout's commit added.
keep_bench_json() { # BENCH_JSON OUT
    mkdir -p "$(dirname "$2")"
    python3 - "$1" "$2" "$(git rev-parse --short HEAD)" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
doc["commit"] = sys.argv[3]
json.dump(doc, open(sys.argv[2], "w"), indent=1)
PY
}

# The CPU's model name and the number of cores (Linux /proc/cpuinfo).
cpu_cores() {
    echo "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
}

# The adapter KDRAY renders with (the line `kdray info` marks with `*`),
# its double quotes escaped for JSON.
adapter_name() { # KDRAY
    "$1" info 2>/dev/null | grep '^\*' | sed 's/^\* //;s/"/\\"/g'
}

# Writes OUT, its folder made as needed: a JSON object of the string fields
# NAME=VALUE (in the order given; VALUE is written as it is, so it must
# need no escaping), then LIST, an array of the ITEMs (JSON values), one a
# line.
write_results_json() { # OUT LIST NAME=VALUE... -- ITEM...
    local out=$1 list=$2
    shift 2
    mkdir -p "$(dirname "$out")"
    {
        echo "{"
        while [ "$1" != -- ]; do
            echo "  \"${1%%=*}\": \"${1#*=}\","
            shift
        done
        shift
        echo "  \"$list\": ["
        local i=0
        for item in "$@"; do
            i=$((i + 1))
            if [ "$i" -lt $# ]; then
                echo "    $item,"
            else
                echo "    $item"
            fi
        done
        echo "  ]"
        echo "}"
    } >"$out"
}

# write_results_json with the fields every kept measurement names: the
# machine, the adapter KDRAY renders with, the commit, then the NAME=VALUE
# fields given, then the load average from LOAD_BEFORE (taken when the runs
# began) to now.
write_kept_results() { # OUT LIST KDRAY LOAD_BEFORE NAME=VALUE... -- ITEM...
    local out=$1 list=$2 kdray=$3 load_before=$4
    shift 4
    local fields=()
    while [ "$1" != -- ]; do
        fields+=("$1")
        shift
    done
    shift
    write_results_json "$out" "$list" \
        machine="$(cpu_cores)" \
        adapter="$(adapter_name "$kdray")" \
        commit="$(git rev-parse --short HEAD)" \
        "${fields[@]}" \
        load="$load_before - $(cut -d' ' -f1 /proc/loadavg)" \
        -- "$@"
}

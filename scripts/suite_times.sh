#!/usr/bin/env bash
# The whole suite's time (docs/testing.md, "Tiers"): for each COMMIT, in a
# worktree of its own, `scripts/test.sh` from an empty target directory and
# then again from the warm one, one after the other; the wall time, the
# exit status, the test binaries cargo ran and the tests they passed (read
# from each run's output by scripts/suite_times_table.py), and the load
# average, sampled every 30 s. Writes OUT and prints the table
# scripts/suite_times_table.py makes of it. Each run builds a debug target
# of its own (about 20 GB); it is removed after the commit's two runs.
#
#   scripts/suite_times.sh OUT COMMIT...   # e.g. docs/results/suite-times.json 0424dbc HEAD
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
out=$1
shift
work=$(mktemp -d)
trap 'kill "$sampler" 2>/dev/null; rm -rf "$work"; git worktree prune' EXIT
( while true; do cut -d' ' -f1 /proc/loadavg >>"$work/load"; sleep 30; done ) &
sampler=$!

runs=()
for commit in "$@"; do
    short=$(git rev-parse --short "$commit")
    tree="$work/tree-$short"
    git worktree add -q --detach "$tree" "$commit"
    for kind in clean warm; do
        : >"$work/load"
        start=$(date +%s)
        rc=0
        (cd "$tree" && scripts/test.sh) >"$work/$short-$kind.log" 2>&1 || rc=$?
        seconds=$(($(date +%s) - start))
        counts=$(python3 scripts/suite_times_table.py count "$work/$short-$kind.log")
        load=$(sort -n "$work/load" | sed -n '1p;$p' | paste -sd' ' | sed 's/ / - /')
        runs+=("{\"commit\": \"$short\", \"target\": \"$kind\", \"seconds\": $seconds, \"exit\": $rc, \"load\": \"$load\", $counts}")
    done
    rm -rf "$tree/target"
    git worktree remove --force "$tree"
done
write_kept_results "$out" runs target/release/kdray "$(cut -d' ' -f1 /proc/loadavg)" \
    -- "${runs[@]}"
python3 scripts/suite_times_table.py table "$out"

#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "OBJ load" from the JSON
scripts/obj_load.sh writes: per scene, its objects and file size, and the
median (and range) over its runs of the load, the k-d tree's build and the
upload, and the peak resident set.

    python3 scripts/obj_load_table.py docs/results/obj-load.json
"""

import statistics
import sys

import results_table


def seconds(values):
    """Median and range of millisecond figures, in seconds."""
    values = [v / 1e3 for v in values]
    return f"{statistics.median(values):.2f} s ({min(values):.2f} - {max(values):.2f})"


def main():
    doc = results_table.load(sys.argv[1])
    cases = results_table.grouped(doc["runs"], "case")
    print(results_table.provenance(doc))
    print()
    print("| scene | objects | file | load | k-d build | upload | peak resident set | runs |")
    print("| --- | --: | --: | --: | --: | --: | --: | --: |")
    for name, runs in cases.items():
        r = [x["run"] for x in runs]
        peak = statistics.median(x["peak_host_mib"] for x in r)
        print(f"| {name} | {r[0]['n']:,} | {runs[0]['file_bytes'] / 1e6:.1f} MB "
              f"| {seconds(x['scene_ms'] for x in r)} | {seconds(x['build_ms'] for x in r)} "
              f"| {seconds(x['upload_ms'] for x in r)} | {peak / 1024:.2f} GiB | {len(r)} |")


if __name__ == "__main__":
    main()

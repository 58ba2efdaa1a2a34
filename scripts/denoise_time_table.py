#!/usr/bin/env python3
"""Prints docs/benchmarks.md's "Denoising" table from the JSON
scripts/denoise_time.sh writes: per image size, the median over the
rounds (and the range) of kdray's GPU denoise and of native Open Image
Denoise's on the CPU, colour, albedo and normal in, and their ratio;
beside them each one's set-up (kdray: compiling the pipelines and
uploading the weights; OIDN: committing the filter).

    python3 scripts/denoise_time_table.py docs/results/denoise-time.json
"""

import statistics
import sys

import results_table


def main(path):
    doc = results_table.load(path)
    print(f"{results_table.provenance(doc)} kdray's {doc['build']} build; {doc['oidn']}.")
    print()
    print("| size | tiles | kdray denoise, s | OIDN denoise, s | kdray / OIDN | kdray set-up, s | OIDN set-up, s |")
    print("| --- | --: | --: | --: | --: | --: | --: |")
    for size, runs in results_table.grouped(doc["runs"], "size").items():
        tools = results_table.grouped(runs, "tool", lambda r: r["stats"])
        kdray, oidn = tools["kdray"], tools["oidn"]

        def cell(stats, key):
            values = [s[key] / 1e3 for s in stats]
            return statistics.median(values), f"{statistics.median(values):.2f} ({min(values):.2f} - {max(values):.2f})"

        k, k_text = cell(kdray, "denoise_ms")
        o, o_text = cell(oidn, "denoise_ms")
        print(f"| {size.replace('x', ' x ')} | {kdray[0]['tiles']} | {k_text} | {o_text} | {k / o:.1f} "
              f"| {cell(kdray, 'setup_ms')[0]:.2f} | {cell(oidn, 'setup_ms')[0]:.2f} |")


if __name__ == "__main__":
    main(sys.argv[1])

#!/usr/bin/env python3
"""Prints docs/benchmarks.md's equal-time table from the JSON
scripts/equal_time.py writes: per scene and time budget T, kdray and
Mitsuba 3 each with the samples per pixel that fit T, the wall time the
run took, the denoiser's share of it (kdray's own denoiser; OIDN for
Mitsuba) and Mitsuba's kernel compilation, and the error against the
reference of the image alone and denoised (relative MSE, HDR-FLIP).

    python3 scripts/equal_time_table.py docs/results/equal-time.json
"""

import sys

import results_table

NAMES = {"kdray": ("kdray", "kdray + its denoiser"), "mitsuba": ("Mitsuba", "Mitsuba + OIDN")}


def main(path):
    doc = results_table.load(path)
    sizes = ", ".join(f"{s['scene']} {s['width']} x {s['height']}" for s in doc["scenes"])
    print(f"{results_table.provenance(doc)} kdray's {doc['build']} build; {doc['mitsuba']}; {doc['oidn']}. "
          f"Sizes: {sizes}. Reference: Mitsuba at {doc['reference_spp']} samples a pixel, another seed. "
          f"`uptime`: \"{doc['uptime_before']}\" before, \"{doc['uptime_after']}\" after.")
    print()
    print("| scene | T, s | renderer | spp | took, s | denoise, s (share) | compile, s | rel. MSE | FLIP |")
    print("| --- | --: | --- | --: | --: | --: | --: | --: | --: |")
    for r in doc["runs"]:
        alone, denoised = NAMES[r["renderer"]]
        jit = f"{r['jit_s']:.1f}" if "jit_s" in r else "-"
        share = f"{r['denoise_s']:.1f} ({100 * r['denoise_s'] / r['wall_s']:.0f}%)"
        head = f"| {r['scene']} | {r['seconds']:g} |"
        n, d = r["noisy"], r["denoised"]
        print(f"{head} {alone} | {r['spp']} | {r['wall_s'] - r['denoise_s']:.1f} | - | {jit} "
              f"| {n['rel_mse']:.4f} | {n['flip']:.3f} |")
        print(f"{head} {denoised} | {r['spp']} | {r['wall_s']:.1f} | {share} | {jit} "
              f"| {d['rel_mse']:.4f} | {d['flip']:.3f} |")


if __name__ == "__main__":
    main(sys.argv[1])

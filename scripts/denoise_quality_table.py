#!/usr/bin/env python3
"""Prints docs/benchmarks.md's denoising quality table from the JSON
scripts/denoise_quality.py writes: per scene and samples per pixel, the
noisy and the denoised image's relative MSE and HDR-FLIP against the
high-sample reference, and how many times lower the denoised error is.

    python3 scripts/denoise_quality_table.py docs/results/denoise-quality.json
"""

import sys

import results_table


def main(path):
    doc = results_table.load(path)
    print(f"{results_table.provenance(doc)} Reference: {doc['reference_spp']} samples a pixel, another seed.")
    print()
    print("| scene | size | spp | rel. MSE noisy | rel. MSE denoised | lower by | FLIP noisy | FLIP denoised | lower by |")
    print("| --- | --- | --: | --: | --: | --: | --: | --: | --: |")
    for r in doc["runs"]:
        n, d = r["noisy"], r["denoised"]
        print(f"| {r['scene']} | {r['width']} x {r['height']} | {r['spp']} | {n['rel_mse']:.4f} | {d['rel_mse']:.4f} "
              f"| {n['rel_mse'] / d['rel_mse']:.1f}x | {n['flip']:.3f} | {d['flip']:.3f} | {n['flip'] / d['flip']:.1f}x |")


if __name__ == "__main__":
    main(sys.argv[1])

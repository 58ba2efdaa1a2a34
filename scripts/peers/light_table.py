#!/usr/bin/env python3
"""Prints the Markdown tables of docs/peers.md's "Light sampling against
Mitsuba 3" (and docs/benchmarks.md's "Light sampling") from the results
scripts/peers/mitsuba_path.py (`compare --save light_NAME`) and
scripts/peers/light_sampling.py (`--save light_error_NAME`) wrote:

    python3 scripts/peers/light_table.py convergence scripts/peers/results
    python3 scripts/peers/light_table.py error scripts/peers/results

`convergence`: per scene, kdray against Mitsuba at equal samples by 16 x
16... block means (the block size the run used), with Mitsuba's seed 1
against seed 0 as the floor. `error`: per scene, the relative MSE of each
renderer's images against the Mitsuba reference at each samples count.
"""

import json
import os
import sys

# Scene name (results file suffix) and what it holds, in table order.
SCENES = [
    ("mixed", "ground, 2 balls, a point light, a directional light, an emissive torus of 5,120 triangles"),
    ("sky_mesh", "a sky image (128 x 64) and the emissive torus"),
    ("city", "400 emissive spheres, powers over 3 orders of magnitude"),
    ("one_bright", "1 bright emissive sphere (81% of the power), 200 dim ones"),
]


def load(folder, name):
    path = os.path.join(folder, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def trio(values, fmt):
    return "/".join(fmt.format(v) for v in values)


def convergence(folder):
    print("| scene | lights | samples | block | mean block difference % (floor) | image ratio kdray / Mitsuba (floor) | within noise |")
    print("| --- | --- | ---: | ---: | --- | --- | --- |")
    load_lines = []
    for name, what in SCENES:
        r = load(folder, "light_" + name)
        e = load(folder, "light_error_" + name)
        if r is None:
            continue
        kd = r["kdray_vs_mitsuba"]
        fl = r["noise_floor_mitsuba_seed1_vs_seed0"]
        mean = trio([kd[c]["block_rel_mean"] * 100 for c in "rgb"], "{:.2f}")
        floor = trio([fl[c]["block_rel_mean"] * 100 for c in "rgb"], "{:.2f}")
        ratio = trio([kd[c]["image_ratio"] for c in "rgb"], "{:.4f}")
        fratio = trio([fl[c]["image_ratio"] for c in "rgb"], "{:.4f}")
        lights = lights_cell(e["lights"]) if e else ""
        print(
            f"| `{r['scene']}`: {what} | {lights} | {r['spp']} | {r['block']} | {mean} ({floor}) "
            f"| {ratio} ({fratio}) | {'yes' if r['within_noise'] else 'no'} |"
        )
        sky = r.get("sky_mismatch_mitsuba_vs_kdray")
        if sky:
            load_lines.append(
                f"- `{r['scene']}`: Mitsuba's sky against kdray's over {sky['directions']:,} random directions: "
                f"means differ by {trio([x * 100 for x in sky['mean_rel_diff']], '{:.2f}')}%, "
                f"mean absolute difference {trio([x * 100 for x in sky['mean_abs_diff_over_mean']], '{:.1f}')}% of the mean."
            )
    print()
    for line in load_lines:
        print(line)


def lights_cell(lights):
    return f"kdray {lights['kdray_entries']:,} entries, Mitsuba {lights['mitsuba_emitters']:,} emitters"


def error(folder):
    rows = []
    spps = []
    for name, what in SCENES:
        e = load(folder, "light_error_" + name)
        if e is None:
            continue
        rows.append((name, e))
        for run in e["runs"]:
            if run["spp"] not in spps:
                spps.append(run["spp"])
    spps.sort()
    head = "| scene | lights |"
    rule = "| --- | --- |"
    for spp in spps:
        head += f" kdray {spp} spp | Mitsuba {spp} spp | kdray / Mitsuba | Mitsuba by power {spp} spp |"
        rule += " ---: | ---: | ---: | ---: |"
    head += " reference noise |"
    rule += " ---: |"
    print(head)
    print(rule)
    for name, e in rows:
        cells = [f"`{e['scene']}`", lights_cell(e["lights"])]
        by_spp = {run["spp"]: run for run in e["runs"]}
        for spp in spps:
            run = by_spp.get(spp)
            if run is None:
                cells += ["", "", "", ""]
                continue
            power = run.get("mitsuba_power_weights_mean")
            cells += [
                f"{run['kdray_mean']:.4f}",
                f"{run['mitsuba_mean']:.4f}",
                f"{run['kdray_over_mitsuba']:.2f}",
                f"{power:.4f}" if power is not None else "not run",
            ]
        cells.append(f"{e['reference_noise_estimate']:.5f}")
        print("| " + " | ".join(cells) + " |")
    print()
    if rows:
        e = rows[0][1]
        seeds = len(e["runs"][0]["kdray_rel_mse"])
        print(
            f"- Relative MSE, {e['rel_mse']}; the mean of {seeds} images per cell (kdray seeds 1 - {seeds}); "
            f"reference: Mitsuba at {e['reference']['spp']:,} samples per pixel; {e['width']} x {e['height']} pixels."
        )
        spread = max(
            (max(v) - min(v)) / (sum(v) / len(v))
            for _, e in rows
            for run in e["runs"]
            for v in (run["kdray_rel_mse"], run["mitsuba_rel_mse"])
        )
        print(f"- The images of one cell spread by up to {spread * 100:.0f}% of its mean (largest minus smallest).")
        for name, e in rows:
            runs = [run for run in e["runs"] if "kdray_over_mitsuba_surface" in run]
            if runs:
                ratios = ", ".join(f"{run['kdray_over_mitsuba_surface']:.2f} at {run['spp']} spp" for run in runs)
                print(
                    f"- `{e['scene']}` over the {runs[0]['surface_pixels']:,} pixels that show no emitter directly "
                    f"({e['surface']}): kdray / Mitsuba {ratios}."
                )
        print(f"- kdray on {e.get('kdray_adapter')}; {e['mitsuba']}; {e['machine']['cpu']}, {e['machine']['cpus']} cores.")
        for name, e in rows:
            before = e["uptime_before"].split("load average:")[-1].strip()
            after = e["uptime_after"].split("load average:")[-1].strip()
            print(f"- `{e['scene']}`: load average {before} before, {after} after.")


def main():
    mode, folder = sys.argv[1], sys.argv[2]
    if mode == "convergence":
        convergence(folder)
    elif mode == "error":
        error(folder)
    else:
        sys.exit(f"unknown mode {mode!r}: convergence or error")


if __name__ == "__main__":
    main()

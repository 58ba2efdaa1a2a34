#!/usr/bin/env python3
"""Equal-time quality (docs/benchmarks.md, "Denoising"): the error kdray's
path tracer leaves after T seconds, noisy and denoised (`render --denoise`),
beside Mitsuba 3's (llvm_ad_rgb) after the same T, alone and with native
Open Image Denoise 1.4.3 run on its output, all against one reference.

    pip install OpenEXR==3.5.3 flip-evaluator numpy oidn==0.2.1  # this Python
    MITSUBA_PYTHON=/path/to/python  # a Python with mitsuba (scripts/peers/mitsuba_path.py)
    python3 scripts/equal_time.py [--kdray BIN] [--out JSON] [--seconds T ...] [--reference-spp N]

The scenes: scenes/peers/path_cornell.toml at 128 x 128 and
scenes/peers/path_bunny_sky.toml at 192 x 108 (Mitsuba expresses both
exactly; scripts/peers/mitsuba_path.py converts them). Neither renderer has
a time limit, so each is given samples per pixel to fit T: per scene, each
is timed at two sample counts (a fit of fixed cost plus cost per sample),
the count for T taken from the fit, and a run more than 10% off T run
again once with the samples the difference buys added or taken away (the
nearer of the two kept). Every run is a fresh
process, timed by the wall clock from start to written image, as a user
waits for it:
- kdray: `render --samples N --denoise -o X.exr`, everything included
  (start-up, scene and tree build, kernel compilation, rendering, the
  denoise, writing). Its noisy image is the same run's X.noisy.exr. The
  denoiser's share is the set-up plus denoise `kdray denoise --stats`
  reports on the same inputs, over the render's wall time.
- Mitsuba: scripts/peers/mitsuba_timed.py (run by MITSUBA_PYTHON, default
  python3) with an empty Dr.Jit kernel cache, so that its LLVM compilation
  is counted, as kdray's is (its share is reported apart); the conversion
  of the kdray scene is left out. Its path integrator is wrapped in the
  `aov` integrator for OIDN's albedo and normal in the same run. OIDN's
  time (scripts/oidn_denoise.py --stats: filter commit and execution) is
  counted in the budget, as kdray's denoise is: so "Mitsuba alone" is the
  image of the run that left room for OIDN.
The reference: Mitsuba at --reference-spp (default 4096) samples per
pixel, path integrator, another seed; it is kept in --reference-dir
(default /tmp/kdray-equal-time) for the next run. Relative MSE and
HDR-FLIP as scripts/denoise_quality.py computes them. Renders alternate
between kdray and Mitsuba; `uptime` is recorded before and after. Writes
OUT (default docs/results/equal-time.json) and prints the table
scripts/equal_time_table.py makes of it.
"""

import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from denoise_quality import flip_hdr, provenance, read_rgb, relative_mse  # noqa: E402

SCENES = [
    ("cornell", "scenes/peers/path_cornell.toml", (128, 128)),
    ("bunny_sky", "scenes/peers/path_bunny_sky.toml", (192, 108)),
]
# A run longer than this times T is run again with fewer samples.
OVERRUN = 1.1


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def timed(cmd, env=None):
    """(wall seconds, stdout) of cmd, which must succeed."""
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"equal_time.py: failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}")
    return wall, p.stdout


def last_json(text):
    return json.loads(text.strip().splitlines()[-1])


class Kdray:
    name = "kdray"

    def __init__(self, binary, work):
        self.binary, self.work = binary, work

    def run(self, scene, size, spp, tag):
        out = os.path.join(self.work, f"kdray.{tag}.exr")
        wall, _ = timed([self.binary, "render", scene, "--width", str(size[0]), "--height", str(size[1]),
                         "--samples", str(spp), "--seed", "2", "--denoise", "-o", out])
        inputs = [out.replace(".exr", ".noisy.exr"), "--albedo", out.replace(".exr", ".albedo.exr"),
                  "--normal", out.replace(".exr", ".normal.exr")]
        _, text = timed([self.binary, "denoise", *inputs, "-o", os.path.join(self.work, "kdray.again.exr"),
                         "--stats"])
        d = last_json(text)
        denoise_s = (d["setup_ms"] + d["denoise_ms"]) / 1e3
        return {"spp": spp, "wall_s": wall, "denoise_s": denoise_s, "noisy": inputs[0], "denoised": out}


class Mitsuba:
    name = "mitsuba"

    def __init__(self, python, work):
        self.python, self.work = python, work
        self.version = None

    def render(self, scene, size, spp, seed, out, aov, cold):
        env = dict(os.environ)
        if cold:
            # Dr.Jit keeps compiled kernels in $HOME/.drjit: an empty HOME compiles all.
            env["HOME"] = tempfile.mkdtemp(dir=self.work)
        cmd = [self.python, os.path.join(HERE, "peers/mitsuba_timed.py"), scene, "--width", str(size[0]),
               "--height", str(size[1]), "--spp", str(spp), "--seed", str(seed), "-o", out]
        wall, text = timed(cmd + (["--aov"] if aov else []), env)
        stats = last_json(text)
        stats["wall_s"] = wall - stats["convert_s"]
        return stats

    def run(self, scene, size, spp, tag):
        out = os.path.join(self.work, f"mitsuba.{tag}.exr")
        stats = self.render(scene, size, spp, 3, out, aov=True, cold=True)
        self.version, self.threads = stats["renderer"], stats["threads"]
        base = out[: -len(".exr")]
        denoised = base + ".oidn.exr"
        _, text = timed([sys.executable, os.path.join(HERE, "oidn_denoise.py"), out, "--albedo",
                         base + ".albedo.exr", "--normal", base + ".normal.exr", "-o", denoised, "--stats"])
        d = last_json(text)
        denoise_s = (d["setup_ms"] + d["denoise_ms"]) / 1e3
        # The wall time counts the denoise, as kdray's does.
        return {"spp": spp, "wall_s": stats["wall_s"] + denoise_s, "denoise_s": denoise_s,
                "jit_s": stats["jit_s"], "import_s": stats["import_s"], "noisy": out, "denoised": denoised}


def fit(renderer, scene, size, low, high):
    """(fixed seconds, seconds per sample per pixel) from runs at low and high spp."""
    a = renderer.run(scene, size, low, f"fit{low}")
    b = renderer.run(scene, size, high, f"fit{high}")
    per = (b["wall_s"] - a["wall_s"]) / (high - low)
    if per <= 0:
        # The load's noise outweighed the samples: all of the time to them, an upper bound.
        per = b["wall_s"] / high
    return {"fixed_s": max(a["wall_s"] - per * low, 0.0), "per_spp_s": per,
            "runs": [{"spp": r["spp"], "wall_s": r["wall_s"]} for r in (a, b)]}


def spp_for(seconds, model):
    return max(1, math.floor((seconds - model["fixed_s"]) / model["per_spp_s"]))


def within(renderer, scene, size, seconds, model, tag):
    """A run whose wall time is near `seconds`: where the first is off by
    more than OVERRUN, a second with as many samples more or fewer as the
    difference buys at the fit's cost per sample, the nearer of the two kept."""
    run = renderer.run(scene, size, spp_for(seconds, model), tag)
    if seconds / OVERRUN <= run["wall_s"] <= OVERRUN * seconds:
        return run
    spp = max(1, run["spp"] + math.floor((seconds - run["wall_s"]) / model["per_spp_s"]))
    spp = min(spp, 4 * run["spp"] + 16)  # a fit the load misled asks no more than this
    if spp == run["spp"]:
        return run
    again = renderer.run(scene, size, spp, tag + ".again")
    return min((run, again), key=lambda r: abs(math.log(r["wall_s"] / seconds)))


def errors(path, reference):
    image = read_rgb(path)
    return {"rel_mse": relative_mse(image, reference), "flip": flip_hdr(image, reference)}


def reference(mitsuba, scene, size, spp, folder):
    """Mitsuba's image at spp (seed 1), kept in folder under a name of the scene's content."""
    with open(scene, "rb") as f:
        key = hashlib.sha256(f.read() + f"{size} {spp}".encode()).hexdigest()[:16]
    path = os.path.join(folder, f"{os.path.basename(scene)[:-5]}-{size[0]}x{size[1]}-{spp}-{key}.exr")
    seconds = None
    if not os.path.exists(path):
        os.makedirs(folder, exist_ok=True)
        seconds = mitsuba.render(scene, size, spp, 1, path, aov=False, cold=False)["wall_s"]
    return read_rgb(path), seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kdray", default=os.path.join(ROOT, "target/release/kdray"))
    parser.add_argument("--mitsuba-python", default=os.environ.get("MITSUBA_PYTHON", "python3"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs/results/equal-time.json"))
    parser.add_argument("--seconds", type=float, nargs="+", default=[15, 30, 60])
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--reference-dir", default="/tmp/kdray-equal-time")
    args = parser.parse_args()
    os.chdir(ROOT)
    kdray_bin = os.path.abspath(args.kdray)
    load_before, uptime_before = open("/proc/loadavg").read().split()[0], uptime()
    scenes, runs = [], []
    with tempfile.TemporaryDirectory() as work:
        kdray, mitsuba = Kdray(kdray_bin, work), Mitsuba(args.mitsuba_python, work)
        for name, scene, size in SCENES:
            ref, ref_seconds = reference(mitsuba, scene, size, args.reference_spp, args.reference_dir)
            models = {}
            for r, (low, high) in ((kdray, (1, 32)), (mitsuba, (1, 256))):
                models[r.name] = fit(r, scene, size, low, high)
            scenes.append({"scene": name, "file": scene, "width": size[0], "height": size[1],
                           "reference_seconds": ref_seconds, "fits": models})
            for seconds in args.seconds:
                for r in (kdray, mitsuba):
                    run = within(r, scene, size, seconds, models[r.name], f"{name}.{seconds:g}")
                    row = {"scene": name, "seconds": seconds, "renderer": r.name,
                           **{k: v for k, v in run.items() if k not in ("noisy", "denoised")},
                           "noisy": errors(run["noisy"], ref), "denoised": errors(run["denoised"], ref)}
                    print(json.dumps(row), file=sys.stderr)
                    runs.append(row)
    doc = provenance(kdray_bin)
    doc["build"] = os.path.basename(os.path.dirname(kdray_bin))
    doc["mitsuba"] = f"{mitsuba.version}, {mitsuba.threads} threads"
    doc["oidn"] = "Open Image Denoise 1.4.3 (oidn wheel 0.2.1), CPU device"
    doc["reference_spp"] = args.reference_spp
    doc["load"] = f"{load_before} - {open('/proc/loadavg').read().split()[0]}"
    doc["uptime_before"], doc["uptime_after"] = uptime_before, uptime()
    doc["scenes"], doc["runs"] = scenes, runs
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
    os.replace(tmp, args.out)
    subprocess.run([sys.executable, os.path.join(HERE, "equal_time_table.py"), args.out], check=True)


if __name__ == "__main__":
    main()

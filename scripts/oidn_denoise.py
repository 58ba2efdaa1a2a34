#!/usr/bin/env python3
"""Denoises an HDR image with native Open Image Denoise 1.4.3 (the RT
filter), the reference `kdray denoise` is checked against.

    pip install oidn==0.2.1 OpenEXR==3.5.3
    scripts/oidn_denoise.py IN.exr [--albedo A.exr --normal N.exr] -o OUT.exr [--stats]

The `oidn` wheel ships OIDN 1.4.3's shared library; its Python binding
lacks oidnSetFilter1b, so the library is called through ctypes here (its
bundled libtbb loaded first, globally, so the library finds it). The
filter runs as OIDN's example tool runs it for HDR input: `hdr` on,
autoexposure, default memory limit; float3 images in and out. `--stats`
prints one JSON object: the filter's commit (OIDN builds its network
there) and its execution, in wall-clock milliseconds, and the machine's
cores (OIDN's default device uses a thread per core).
"""

import argparse
import ctypes
import importlib.util
import json
import os
import sys
import time

import numpy as np
import OpenEXR

OIDN_VERSION = "1.4.3"
OIDN_FORMAT_FLOAT3 = 3
OIDN_DEVICE_TYPE_CPU = 1


def load_library():
    spec = importlib.util.find_spec("oidn")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("oidn_denoise.py: the oidn wheel is not installed: pip install oidn==0.2.1")
    folder = os.path.join(list(spec.submodule_search_locations)[0], "lib.linux.x64")
    ctypes.CDLL(os.path.join(folder, "libtbb.so.12.5"), mode=ctypes.RTLD_GLOBAL)
    lib = ctypes.CDLL(os.path.join(folder, f"libOpenImageDenoise.so.{OIDN_VERSION}"))
    lib.oidnNewDevice.restype = ctypes.c_void_p
    lib.oidnNewDevice.argtypes = [ctypes.c_int]
    lib.oidnCommitDevice.argtypes = [ctypes.c_void_p]
    lib.oidnNewFilter.restype = ctypes.c_void_p
    lib.oidnNewFilter.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    lib.oidnSetSharedFilterImage.argtypes = [
        ctypes.c_void_p, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_int,
        ctypes.c_size_t, ctypes.c_size_t, ctypes.c_size_t, ctypes.c_size_t, ctypes.c_size_t]
    lib.oidnSetFilter1b.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_bool]
    lib.oidnCommitFilter.argtypes = [ctypes.c_void_p]
    lib.oidnExecuteFilter.argtypes = [ctypes.c_void_p]
    lib.oidnGetDeviceError.restype = ctypes.c_int
    lib.oidnGetDeviceError.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_char_p)]
    lib.oidnReleaseFilter.argtypes = [ctypes.c_void_p]
    lib.oidnReleaseDevice.argtypes = [ctypes.c_void_p]
    return lib


def read_rgb(path):
    """An EXR's R, G, B channels as a contiguous float32 (height, width, 3) array."""
    try:
        with OpenEXR.File(path, separate_channels=True) as f:
            channels = f.channels()
            planes = [channels[name].pixels for name in ("R", "G", "B")]
    except Exception as e:  # the binding raises several kinds
        sys.exit(f"oidn_denoise.py: {path}: cannot read as OpenEXR RGB: {e}")
    return np.ascontiguousarray(np.stack(planes, axis=-1), dtype=np.float32)


def write_rgb(path, rgb):
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    channels = {name: np.ascontiguousarray(rgb[..., i]) for i, name in enumerate("RGB")}
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), f".{os.path.basename(path)}.tmp-{os.getpid()}.exr")
    with OpenEXR.File(header, channels) as f:
        f.write(tmp)
    os.replace(tmp, path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("--albedo")
    parser.add_argument("--normal")
    parser.add_argument("-o", "--output", required=True)
    parser.add_argument("--stats", action="store_true")
    args = parser.parse_args()
    if args.normal and not args.albedo:
        sys.exit("oidn_denoise.py: --normal needs --albedo")
    color = read_rgb(args.input)
    height, width, _ = color.shape
    images = {"color": color}
    for name in ("albedo", "normal"):
        path = getattr(args, name)
        if path:
            images[name] = read_rgb(path)
            if images[name].shape != color.shape:
                sys.exit(f"oidn_denoise.py: {path}: {images[name].shape[1]}x{images[name].shape[0]}, "
                         f"the colour is {width}x{height}")
    output = np.zeros_like(color)

    lib = load_library()
    device = lib.oidnNewDevice(OIDN_DEVICE_TYPE_CPU)
    lib.oidnCommitDevice(device)
    filt = lib.oidnNewFilter(device, b"RT")
    for name, image in list(images.items()) + [("output", output)]:
        lib.oidnSetSharedFilterImage(filt, name.encode(), image.ctypes.data, OIDN_FORMAT_FLOAT3,
                                     width, height, 0, 0, 0)
    lib.oidnSetFilter1b(filt, b"hdr", True)
    started = time.perf_counter()
    lib.oidnCommitFilter(filt)
    committed = time.perf_counter()
    lib.oidnExecuteFilter(filt)
    executed = time.perf_counter()
    message = ctypes.c_char_p()
    if lib.oidnGetDeviceError(device, ctypes.byref(message)) != 0:
        sys.exit(f"oidn_denoise.py: OIDN: {message.value.decode() if message.value else 'error'}")
    lib.oidnReleaseFilter(filt)
    lib.oidnReleaseDevice(device)
    write_rgb(args.output, output)
    if args.stats:
        threads = os.cpu_count()
        print(json.dumps({"width": width, "height": height, "input_channels": 3 * len(images),
                          "threads": threads, "setup_ms": (committed - started) * 1e3,
                          "denoise_ms": (executed - committed) * 1e3}))


if __name__ == "__main__":
    main()

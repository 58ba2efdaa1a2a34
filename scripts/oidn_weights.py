#!/usr/bin/env python3
"""Extracts the denoiser's weights from Intel Open Image Denoise 1.4.3.

    pip install oidn==0.2.1
    scripts/oidn_weights.py [--out assets/denoise]

The `oidn` wheel ships OIDN 1.4.3's shared library for Linux, which embeds
each trained network of the RT filter as a Tensor Archive (TZA) blob in its
read-only data, one symbol per blob: `oidn::blobs::weights::rt_hdr` and so
on (the library is not stripped). kdray needs two of them:

    rt_hdr_alb_nrm   HDR colour + albedo + normal (enc_conv0 reads 9 channels)
    rt_hdr           HDR colour only              (enc_conv0 reads 3 channels)

The blobs are found by their symbols' names in the ELF symbol table (the
`ldr` variants have the same shapes, so shapes alone cannot tell them
apart), checked as TZA (magic, version, every tensor inside the blob, the
first convolution's input channels) and written unchanged as NAME.tza.
Nothing here imports the wheel's module (which needs its libtbb loaded
first); the library is only read as bytes.
"""

import argparse
import hashlib
import importlib.util
import os
import struct
import sys

OIDN_VERSION = "1.4.3"
# Blob name -> input channels of its first convolution.
WANTED = {"rt_hdr_alb_nrm": 9, "rt_hdr": 3}
TZA_MAGIC = 0x41D7


def wheel_library():
    spec = importlib.util.find_spec("oidn")
    if spec is None or not spec.submodule_search_locations:
        sys.exit("oidn_weights.py: the oidn wheel is not installed: pip install oidn==0.2.1")
    folder = list(spec.submodule_search_locations)[0]
    path = os.path.join(folder, "lib.linux.x64", f"libOpenImageDenoise.so.{OIDN_VERSION}")
    if not os.path.isfile(path):
        sys.exit(f"oidn_weights.py: {path}: not found (the wheel must be oidn==0.2.1, OIDN {OIDN_VERSION})")
    return path


def elf_symbols(data):
    """Name -> (file offset, size) of every symbol of .symtab in a 64-bit
    little-endian ELF file whose value lies in a section with file bytes."""
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        sys.exit("oidn_weights.py: the library is not a 64-bit little-endian ELF file")
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = []
    for i in range(shnum):
        (name, kind, flags, addr, offset, size, link, info, align, entsize) = struct.unpack_from(
            "<IIQQQQIIQQ", data, shoff + i * shentsize)
        sections.append((kind, addr, offset, size, link, entsize))
    symbols = {}
    for kind, _, offset, size, link, entsize in sections:
        if kind != 2:  # SHT_SYMTAB
            continue
        strtab = sections[link]
        for at in range(offset, offset + size, entsize):
            name_at, info, other, shndx, value, sym_size = struct.unpack_from("<IBBHQQ", data, at)
            if shndx == 0 or shndx >= len(sections):
                continue
            s_kind, s_addr, s_offset, s_size, _, _ = sections[shndx]
            if s_kind == 8 or not (s_addr <= value < s_addr + s_size):  # SHT_NOBITS
                continue
            start = strtab[2] + name_at
            name = data[start:data.index(b"\0", start)].decode("ascii", "replace")
            symbols[name] = (s_offset + value - s_addr, sym_size)
    return symbols


def mangled(blob):
    return f"_ZN4oidn5blobs7weights{len(blob)}{blob}E"


def tza_tensors(blob):
    """(name, dims, layout, dtype, offset) of each tensor; exits on anything
    outside the blob or not as OIDN 1.4.3 reads it."""
    magic, major, _minor, table = struct.unpack_from("<HBBQ", blob, 0)
    if magic != TZA_MAGIC or major != 2:
        sys.exit("oidn_weights.py: not a version-2 TZA blob")
    count, = struct.unpack_from("<I", blob, table)
    at = table + 4
    tensors = []
    for _ in range(count):
        n, = struct.unpack_from("<H", blob, at)
        name = blob[at + 2:at + 2 + n].decode("utf-8")
        at += 2 + n
        ndims = blob[at]
        dims = struct.unpack_from(f"<{ndims}I", blob, at + 1)
        at += 1 + 4 * ndims
        layout = blob[at:at + ndims].decode("ascii")
        dtype = chr(blob[at + ndims])
        offset, = struct.unpack_from("<Q", blob, at + ndims + 1)
        at += ndims + 9
        count_values = 1
        for d in dims:
            count_values *= d
        if dtype != "f" or offset + 4 * count_values > len(blob):
            sys.exit(f"oidn_weights.py: tensor {name} is not f32 inside the blob")
        tensors.append((name, dims, layout, dtype, offset))
    if at > len(blob):
        sys.exit("oidn_weights.py: the tensor table runs past the blob")
    return tensors


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.normpath(os.path.join(os.path.dirname(__file__), "..", "assets", "denoise")))
    args = parser.parse_args()
    path = wheel_library()
    with open(path, "rb") as f:
        data = f.read()
    symbols = elf_symbols(data)
    os.makedirs(args.out, exist_ok=True)
    for blob_name, input_channels in WANTED.items():
        symbol = mangled(blob_name)
        if symbol not in symbols:
            sys.exit(f"oidn_weights.py: {path} has no symbol {symbol}")
        offset, size = symbols[symbol]
        blob = data[offset:offset + size]
        tensors = {name: (dims, layout) for name, dims, layout, _, _ in tza_tensors(blob)}
        dims, layout = tensors.get("enc_conv0.weight", ((), ""))
        if layout != "oihw" or len(dims) != 4 or dims[1] != input_channels:
            sys.exit(f"oidn_weights.py: {blob_name}: enc_conv0.weight is {dims} {layout}, "
                     f"expected {input_channels} input channels")
        out = os.path.join(args.out, f"{blob_name}.tza")
        with open(out + ".tmp", "wb") as f:
            f.write(blob)
        os.replace(out + ".tmp", out)
        digest = hashlib.sha256(blob).hexdigest()
        print(f"{out}: {size} bytes, {len(tensors)} tensors, sha256 {digest}")


if __name__ == "__main__":
    main()

#!/bin/bash
# Where the CPU spends a `kdray render` inside lavapipe's compiled kernel, on
# the kernel that plain runs execute (AVX-512 where the CPU has it), unlike
# scripts/jit_instructions.sh, whose valgrind makes llvmpipe compile an AVX2
# build (docs/benchmarks.md, "the kernel that runs is not the kernel valgrind
# counts").
#
# usage: scripts/jit_profile.sh KDRAY SCENE [render options...]
#   e.g. scripts/jit_profile.sh target/release/kdray /tmp/direct.json --width 3840 --height 2160
#
# Needs perf and gdb (apt-get install linux-perf gdb) and root or
# kernel.perf_event_paranoid <= 2. perf samples by the kernel's timer
# (cpu-clock, 4 kHz), which works on machines without hardware counters. The
# compiled code lies in anonymous executable mappings that vanish with the
# device, so gdb copies them out as the render finishes. Prints the share of samples
# in the compiled code, its commonest instructions, the share that falls just
# after an indexed load (mostly waiting on memory), and the hottest stretches
# of code, disassembled. Samples skid: one lands on the instruction after
# the one that stalled.
set -euo pipefail
if [ $# -lt 2 ]; then
    sed -n '8,9p' "$0" >&2
    exit 2
fi
kdray=$1
scene=$2
shift 2
for tool in perf gdb objdump python3; do
    command -v "$tool" >/dev/null || { echo "jit_profile.sh: $tool is not installed" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The compiled code lies in anonymous executable mappings that vanish with
# the device (new ones appear as the frame goes on, about one a dispatch,
# holding copies of the same code): gdb stops the render where it renames its
# finished PNG into place, the device still open, and copies them all out.
cat >"$work/dump.gdb" <<GDB
set pagination off
set confirm off
catch syscall rename renameat renameat2
run
python
pid = gdb.selected_inferior().pid
for line in open(f"/proc/{pid}/maps"):
    f = line.split()
    if "x" in f[1] and len(f) == 5:
        lo, hi = f[0].split("-")
        gdb.execute(f"dump binary memory $work/code_{lo}.bin 0x{lo} 0x{hi}")
end
delete
continue
GDB
perf record -q -e cpu-clock -F 4000 -o "$work/perf.data" -- \
    gdb -batch -x "$work/dump.gdb" --args "$kdray" render "$scene" -o "$work/image.png" "$@" \
    >"$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
ls "$work"/code_*.bin >/dev/null 2>&1 || { cat "$work/log" >&2; echo "jit_profile.sh: gdb copied no code" >&2; exit 1; }
perf script -i "$work/perf.data" -F ip,dso 2>/dev/null >"$work/ips.txt"

python3 - "$work" <<'EOF'
import collections, glob, os, re, subprocess, sys

work = sys.argv[1]
samples = collections.Counter()
anonymous = 0  # samples perf could put in no file: compiled code
for line in open(os.path.join(work, "ips.txt")):
    fields = line.split()
    if fields:
        samples[int(fields[0], 16)] += 1
        anonymous += len(fields) > 1 and ("perf-" in fields[1] or "JIT" in line or "unknown" in fields[1])
total = sum(samples.values())
code = []  # (address, instruction, samples)
for path in sorted(glob.glob(os.path.join(work, "code_*.bin"))):
    base = int(os.path.basename(path)[5:-4], 16)
    listing = subprocess.run(
        ["objdump", "-D", "-b", "binary", "-m", "i386:x86-64", "--adjust-vma=%#x" % base, path],
        capture_output=True, text=True, check=True,
    ).stdout
    for line in listing.splitlines():
        m = re.match(r"\s*([0-9a-f]+):\t(?:[0-9a-f]{2} )+\s*\t(.*)", line)
        if m:
            address = int(m.group(1), 16)
            code.append((address, m.group(2).strip(), samples.get(address, 0)))
code.sort()
in_code = sum(c for _, _, c in code)
print(f"{total} samples, {anonymous} ({anonymous / max(total, 1):.0%}) in code of no file, "
      f"{in_code} of them in the code copied out")
if not in_code:
    sys.exit(0)
ops = collections.Counter()
for _, ins, c in code:
    ops[ins.split()[0] if ins else "?"] += c
print("commonest instructions: " + ", ".join(f"{op} {c / in_code:.1%}" for op, c in ops.most_common(12)))
indexed_load = re.compile(r"\(%r\w+,%r\w+,[48]\)")
after = sum(c for (_, prev, _), (_, _, c) in zip(code, code[1:]) if indexed_load.search(prev) and "rsp" not in prev)
stack = sum(c for _, ins, c in code if "(%rsp" in ins)
print(f"just after an indexed load: {after / in_code:.1%}; on a stack operand: {stack / in_code:.1%}")
window = 48
sums, running = [], 0
for i, (_, _, c) in enumerate(code):
    running += c - (code[i - window][2] if i >= window else 0)
    sums.append((running, i))
chosen = []
for s, i in sorted(sums, reverse=True):
    if all(abs(i - j) > window for j in chosen):
        chosen.append(i)
    if len(chosen) == 3:
        break
for i in chosen:
    stretch = code[max(0, i - window + 1): i + 1]
    print(f"\n{sum(c for _, _, c in stretch) / in_code:.1%} of the kernel's samples:")
    for address, ins, c in stretch:
        print(f"  {address:#x} {c:5d}  {ins}")
EOF

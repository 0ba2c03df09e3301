#!/usr/bin/env python3
"""Where a kernel of Intel's CPU OpenCL runtime spends its time, by instruction.

Intel's runtime JIT-compiles kernels into anonymous memory, so `perf report` shows their
samples only as addresses (in /tmp/perf-PID.map's unnamed range). The program binary that
archwave caches (ARCHWAVE_KERNEL_CACHE, host/cl: "archwave-kernel-binary" header, then the
runtime's ELF) holds the same machine code as an x86-64 object in its `.ocl.obj` section.
This script lifts that object out, disassembles it (objdump), finds where it was loaded by
the base address at which most samples fall on instruction boundaries, and prints the
samples per kernel and the hottest instructions with their neighbours.

Usage (docs/performance.md, "Profiling Intel's runtime by instruction"):
  export ARCHWAVE_KERNEL_CACHE=$PWD/build/kernel-cache
  perf record -e cpu-clock -o perf.data -- build/archwave scenes/cornell.json --device intel ...
  scripts/intel_jit_profile.py perf.data build/kernel-cache/*.bin [--top 12] [--asm out.asm]

With the kernels built with line tables (ARCHWAVE_CL_OPTIONS=-g, docs/cli.md: Intel's runtime
still optimises them), `--lines FUNCTION` also prints that function's samples per source line
(addr2line; inlined code counts at its own header's line).

Each cached binary is tried; those that explain no samples are skipped. A sample's
instruction is the one after the one that cost the time (skid): after a `lock` instruction
it is the atomic's cost.
"""
import argparse
import collections
import re
import struct
import subprocess
import sys
import tempfile


def ocl_object(path):
    """The x86-64 object inside an archwave-cached binary of Intel's runtime, or None."""
    data = open(path, "rb").read()
    elf_at = data.find(b"\x7fELF")
    if elf_at < 0:
        return None
    d = data[elf_at:]
    if len(d) < 64 or d[4] != 2:  # ELF64 only
        return None
    shoff = struct.unpack_from("<Q", d, 0x28)[0]
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", d, 0x3A)
    secs = []
    for i in range(shnum):
        name, _typ, _flags, _addr, off, size = struct.unpack_from("<IIQQQQ", d, shoff + i * shentsize)
        secs.append((name, off, size))
    if shstrndx >= len(secs):
        return None
    stroff = secs[shstrndx][1]
    for name, off, size in secs:
        end = d.index(b"\0", stroff + name)
        if d[stroff + name:end] == b".ocl.obj":
            obj = d[off:off + size]
            inner = obj.find(b"\x7fELF")
            return obj[inner:] if inner >= 0 else None
    return None


def jit_samples(perf_data):
    """Sample counts per address for samples outside any file-backed object."""
    out = subprocess.run(["perf", "script", "-i", perf_data, "-F", "ip,dso"], capture_output=True, text=True).stdout
    counts = collections.Counter()
    for line in out.splitlines():
        parts = line.split()
        if len(parts) == 2 and ("perf-" in parts[1] or "[JIT]" in parts[1] or "unknown" in parts[1]):
            counts[int(parts[0], 16)] += 1
    return counts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("perf_data")
    ap.add_argument("binaries", nargs="+")
    ap.add_argument("--top", type=int, default=12, help="hottest instructions to show per program")
    ap.add_argument("--asm", help="write the annotated disassembly (samples per instruction) here")
    ap.add_argument("--lines", metavar="FUNCTION",
                    help="samples of this function per source line (kernels built with ARCHWAVE_CL_OPTIONS=-g)")
    args = ap.parse_args()
    if args.asm:
        open(args.asm, "w").close()  # one run's listing (the programs are appended below)
    samples = jit_samples(args.perf_data)
    if not samples:
        sys.exit("intel_jit_profile: no JIT samples in " + args.perf_data)
    total = sum(samples.values())
    lo, hi = min(samples), max(samples)
    print(f"{total} samples in JIT code")
    # Each binary: its disassembly and the base at which the most samples fall on its
    # instruction boundaries (votes: every hot address minus every instruction offset). The
    # binaries are then taken greedily, the best first, each claiming the samples in its
    # range, so that a stale binary of the same program (the cache keeps every build) cannot
    # claim another's samples at a shifted base.
    progs = []
    hot = [a for a, _ in samples.most_common(64)]
    for path in args.binaries:
        obj = ocl_object(path)
        if obj is None:
            continue
        with tempfile.NamedTemporaryFile(suffix=".o") as f:
            f.write(obj)
            f.flush()
            asm = subprocess.run(["objdump", "-d", "--no-show-raw-insn", f.name], capture_output=True, text=True).stdout
            syms = []
            for line in subprocess.run(["nm", "-n", f.name], capture_output=True, text=True).stdout.splitlines():
                p = line.split()
                if len(p) == 3 and p[1] in "Tt":
                    syms.append((int(p[0], 16), p[2]))
        lines = asm.splitlines()
        offs = {}
        for i, line in enumerate(lines):
            m = re.match(r"\s+([0-9a-f]+):", line)
            if m:
                offs[int(m.group(1), 16)] = i
        if offs:
            progs.append((path, lines, offs, syms, obj))
    claimed = collections.Counter()
    while progs:
        scored = []
        for k, (path, lines, offs, syms, _) in enumerate(progs):
            votes = collections.Counter(a - o for a in hot if a not in claimed for o in offs)
            best = (0, 0)
            for base, _ in votes.most_common(8):
                hit = sum(n for a, n in samples.items() if a not in claimed and (a - base) in offs)
                best = max(best, (hit, base))
            scored.append((best[0], best[1], k))
        hit, base, k = max(scored)
        path, lines, offs, syms, obj = progs.pop(k)
        if hit < 0.02 * total:
            break
        span = max(offs)
        print(f"\n{path}: loaded at {base:#x}, {hit} samples ({100.0 * hit / total:.1f}%)")
        per = collections.Counter()
        at = collections.Counter()
        for a, n in samples.items():
            off = a - base
            if off not in offs or a in claimed:
                continue
            at[off] += n
            per[symbol_at(syms, off)] += n
        for name, n in per.most_common():
            print(f"  {n:6d}  {100.0 * n / hit:5.1f}%  {name}")
        print(f"  hottest instructions (the line before each is the one that was waited on):")
        for off, n in at.most_common(args.top):
            i = offs[off]
            print(f"  {n:6d}  " + lines[i].strip())
            print(f"          before: " + lines[i - 1].strip())
        if args.lines:
            print_lines(obj, syms, at, args.lines)
        for a, n in samples.items():
            if 0 <= a - base <= span:
                claimed[a] = n
        if args.asm:
            with open(args.asm, "a") as out:
                out.write(f"# {path} (loaded at {base:#x})\n")
                for line in lines:
                    m = re.match(r"\s+([0-9a-f]+):", line)
                    n = at.get(int(m.group(1), 16), 0) if m else 0
                    out.write(f"{n:6d} {line}\n" if m else f"       {line}\n")


def symbol_at(syms, off):
    """The function (syms: (start, name) by address) that holds code offset `off`."""
    name = "?"
    for s, nm in syms:
        if off >= s:
            name = nm
    return name


def print_lines(obj, syms, at, function):
    """Samples per source line of `function` (offsets `at` within the object's code)."""
    offs = [(off, n) for off, n in at.items() if symbol_at(syms, off) == function]
    if not offs:
        return
    with tempfile.NamedTemporaryFile(suffix=".o") as f:
        f.write(obj)
        f.flush()
        where = subprocess.run(["addr2line", "-e", f.name] + [hex(o) for o, _ in offs],
                               capture_output=True, text=True).stdout.splitlines()
    per = collections.Counter()
    for (_, n), w in zip(offs, where):
        per[re.sub(r" \(discriminator \d+\)", "", w).rsplit("/", 1)[-1]] += n
    total = sum(per.values())
    print(f"  {function} by source line ({total} samples; '?' where the line table has none):")
    for w, n in per.most_common(40):
        print(f"  {n:6d}  {100.0 * n / total:5.1f}%  {w}")


if __name__ == "__main__":
    main()

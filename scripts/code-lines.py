#!/usr/bin/env python3
"""How much code a profiled run executes: the distinct 64-byte code lines it touches.

A mesher whose hot code spans more cache lines pays more when it starts with cold caches
(each line is fetched once per mesh), whatever its instruction count. This reads a callgrind
profile taken with instruction-level counts and prints the code lines executed at least
`--min-count` times (the number of meshes, to leave out first-call paths such as buffer
growth), by function and, for one function, by the innermost `mesher::blocky` function
inlined into it:

    valgrind --tool=callgrind --callgrind-out-file=cg.out --dump-instr=yes --dump-line=no \\
        --toggle-collect='*mesh_chunk*' \\
        target/release/examples/profile_blocky terrain greedy-noao 20 32
    scripts/code-lines.py cg.out target/release/examples/profile_blocky --min-count 20 \\
        --inlined mesh_chunk_x86_v3

Needs `objdump` and `addr2line` (binutils).
"""

import argparse
import collections
import os
import re
import subprocess


def executed(profile, binary):
    """Instruction address -> times executed, for the instructions of `binary`."""
    counts = collections.Counter()
    names = {}
    current = None
    last = 0
    skip_next = False
    with open(profile) as f:
        for line in f:
            m = re.match(r"(c?)ob=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(3):
                    names[m.group(2)] = m.group(3).strip()
                if not m.group(1):
                    current = names.get(m.group(2))
                continue
            if line.startswith("calls="):
                # The next cost line is the call's inclusive cost, not an instruction's own.
                skip_next = True
                continue
            m = re.match(r"^(0x[0-9a-f]+|[+-]\d+|\*)\s+(\d+)", line)
            if not m:
                continue
            pos = m.group(1)
            if pos.startswith("0x"):
                last = int(pos, 16)
            elif pos != "*":
                last += int(pos)
            if skip_next:
                skip_next = False
                continue
            if current == binary:
                counts[last] += int(m.group(2))
    return counts


def disassembly(binary):
    """Instruction address -> (size in bytes, symbol)."""
    out = subprocess.run(
        ["objdump", "-d", "--no-show-raw-insn", binary], capture_output=True, text=True
    ).stdout
    addresses = []
    symbol_of = {}
    symbol = None
    for line in out.splitlines():
        m = re.match(r"^([0-9a-f]+) <(.*)>:", line)
        if m:
            symbol = m.group(2)
            continue
        m = re.match(r"^\s+([0-9a-f]+):", line)
        if m:
            a = int(m.group(1), 16)
            addresses.append(a)
            symbol_of[a] = symbol
    addresses.sort()
    return {
        a: (b - a, symbol_of[a]) for a, b in zip(addresses, addresses[1:])
    }


def lines_of(address, size):
    return range(address // 64, (address + size - 1) // 64 + 1)


def innermost_blocky(binary, addresses):
    """Address -> the innermost inlined function whose source is in `mesher/src/blocky`."""
    text = "\n".join(hex(a) for a in addresses)
    out = subprocess.run(
        ["addr2line", "-f", "-i", "-C", "-a", "-e", binary],
        input=text,
        capture_output=True,
        text=True,
    ).stdout.splitlines()
    frames = collections.defaultdict(list)
    current = None
    i = 0
    while i < len(out):
        if out[i].startswith("0x"):
            current = int(out[i], 16)
            i += 1
        elif current is not None and i + 1 < len(out):
            frames[current].append((out[i], out[i + 1]))
            i += 2
        else:
            i += 1
    name_of = {}
    for a, chain in frames.items():
        name_of[a] = "?"
        for function, place in chain:
            if "mesher/src/blocky" in place:
                file = os.path.basename(place.split(":")[0])
                name_of[a] = f"{function.split('<')[0]} ({file})"
                break
    return name_of


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("profile")
    parser.add_argument("binary")
    parser.add_argument("--min-count", type=int, default=1)
    parser.add_argument("--inlined", help="a symbol substring to break down by inlined function")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    counts = {
        a: c for a, c in executed(args.profile, binary).items() if c >= args.min_count
    }
    code = disassembly(binary)
    touched = set()
    by_symbol = collections.defaultdict(set)
    for a in counts:
        size, symbol = code.get(a, (1, "?"))
        for line in lines_of(a, size):
            touched.add(line)
            by_symbol[symbol].add(line)
    executed_bytes = sum(code.get(a, (1, ""))[0] for a in counts)
    print(
        f"{len(touched)} code lines ({len(touched) * 64 / 1024:.1f} KiB) touched, "
        f"{executed_bytes / 1024:.1f} KiB of instructions in them"
    )
    for symbol, lines in sorted(by_symbol.items(), key=lambda kv: -len(kv[1]))[:12]:
        print(f"{len(lines):6} {symbol}")
    if args.inlined:
        inside = [a for a in counts if args.inlined in (code.get(a, (1, ""))[1] or "")]
        by_function = collections.defaultdict(set)
        for a, name in innermost_blocky(binary, inside).items():
            by_function[name].update(lines_of(a, code.get(a, (1, ""))[0]))
        print(f"in {args.inlined}, by inlined function:")
        for name, lines in sorted(by_function.items(), key=lambda kv: -len(kv[1]))[:25]:
            print(f"{len(lines):6} {name}")


if __name__ == "__main__":
    main()

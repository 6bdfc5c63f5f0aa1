#!/usr/bin/env python3
"""Instructions per function of a QEMU firmware run, from QEMU's own trace.

Runs an mps2-an386 (Cortex-M4F) firmware ELF under `qemu-system-arm -icount
shift=0` with the `in_asm`, `exec` and `nochain` logs: `in_asm` lists the
guest instructions of every translation block as QEMU translates it, `exec`
logs every entry into a block with QEMU's handle for it, and a `Stopped
execution` line marks an entry that ran nothing (the instruction budget of
`-icount` ran out). Instructions per block times the runs of the block,
summed by the function each instruction belongs to (through llvm-symbolizer,
inlined functions included; else the ELF's symbols, through llvm-nm or nm),
is an exact per-function instruction count of the run.

    python3 scripts/qemu-profile.py firmware.elf [--top 40] [--workdir DIR]

Build the firmware with FIRMWARE_FRAMES=1 first (the log of one 240x240 frame
is about a gigabyte): `cargo xtask profile` builds and profiles the teapot.
"""
import argparse
import bisect
import collections
import os
import re
import shutil
import subprocess
import sys
import tempfile


def source_name(where):
    """A source location `path:line:column` as the listings give it: the
    library's files by their path under firmware/src (`shading/mod.rs`, so
    that two files named `mod.rs` stay apart), every other file (the core
    library, the harness) by its file name."""
    library = "/firmware/src/"
    if library in where:
        return where.split(library, 1)[1]
    return where.rsplit("/", 1)[-1]


def symbols(elf):
    """Sorted (address, name) of the ELF's function symbols, demangled."""
    nm = shutil.which("llvm-nm") or shutil.which("nm")
    if nm is None:
        sys.exit("qemu-profile: needs llvm-nm or nm")
    out = subprocess.run([nm, "--defined-only", "-C", elf], check=True,
                         capture_output=True, text=True).stdout
    table = []
    for line in out.splitlines():
        parts = line.split(" ", 2)
        if len(parts) == 3 and parts[1] in "tTwW":
            table.append((int(parts[0], 16) & ~1, parts[2]))
    table.sort()
    return table


def short(name):
    """A demangled name without its hash and generic noise."""
    for code, text in (("$LT$", "<"), ("$GT$", ">"), ("$u20$", " "), ("$C$", ","),
                       ("$RF$", "&"), ("$u7b$", "{"), ("$u7d$", "}"), ("$u5b$", "["),
                       ("$u5d$", "]"), ("$u3b$", ";"), ("..", "::")):
        name = name.replace(code, text)
    name = name.lstrip("_")
    name = re.sub(r"::h[0-9a-f]{16}$", "", name)
    name = re.sub(r"<[^<>]*>", "", name)
    name = re.sub(r"<[^<>]*>", "", name)
    return name


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("elf")
    parser.add_argument("--top", type=int, default=40)
    parser.add_argument("--workdir", default=None)
    parser.add_argument("--files", action="store_true",
                        help="also count by source file (of the innermost inlined function)")
    parser.add_argument("--outer", action="store_true",
                        help="also count by the function symbol that holds the code "
                             "(inlined callees counted in their caller)")
    parser.add_argument("--inside", default=None,
                        help="count by source line the code of the function symbols "
                             "matching this text (inlined callees included)")
    parser.add_argument("--annotate", default=None,
                        help="print the disassembly of the function symbols matching this "
                             "text with each instruction's count")
    parser.add_argument("--mix", action="store_true",
                        help="also count by kind of instruction (stack loads and stores, other "
                             "memory, multiplies, branches, ...), in all and per function symbol")
    parser.add_argument("--lines", default=None,
                        help="also count by source line within functions matching this text")
    args = parser.parse_args()
    work = args.workdir or tempfile.mkdtemp(prefix="qemu-profile-")
    os.makedirs(work, exist_ok=True)
    log = os.path.join(work, "trace.log")
    cmd = ["qemu-system-arm", "-M", "mps2-an386", "-cpu", "cortex-m4", "-nographic",
           "-monitor", "none", "-serial", "none",
           "-semihosting-config", "enable=on,target=native", "-icount", "shift=0",
           "-d", "in_asm,exec,nochain", "-D", log, "-kernel", os.path.abspath(args.elf)]
    subprocess.run(cmd, cwd=work, check=True, stdout=subprocess.DEVNULL)

    # QEMU can hold several translation blocks that start at one address: with
    # `-icount`, an instruction that reads a device (the timer) ends a block
    # and is translated again as a block of its own, so the same start has a
    # long and a one-instruction block. A block is therefore known by QEMU's
    # own handle for it, the host address in each `Trace` line, and bound to
    # the instructions of the `IN:` listing that its first run follows. A
    # handle QEMU reuses for new code is bound again; the runs before count
    # with the instructions they ran. A block whose instruction budget ran out
    # as it was entered (every 65,535 instructions under `-icount`) has its
    # `Trace` line but ran nothing; QEMU says so in a `Stopped execution`
    # line, and that run is taken back.
    per_pc = collections.Counter()
    bound = {}           # handle -> [instruction addresses, runs since bound]
    listing = None       # the instructions of the newest `IN:` block
    reading = False
    exec_re = re.compile(r"^Trace \d+: (0x[0-9a-f]+) \[[0-9a-f]+/([0-9a-f]+)/")
    stopped_re = re.compile(r"^Stopped execution of TB chain before (0x[0-9a-f]+) ")
    insn_re = re.compile(r"^0x([0-9a-f]+):")

    def settle(entry):
        for pc in entry[0]:
            per_pc[pc] += entry[1]

    with open(log, "r", errors="replace") as f:
        for line in f:
            if line.startswith("Trace"):
                reading = False
                m = exec_re.match(line)
                if not m:
                    continue
                handle, start = m.group(1), int(m.group(2), 16)
                if listing and listing[0] == start:
                    if handle in bound:
                        settle(bound[handle])
                    bound[handle] = [listing, 0]
                    listing = None
                if handle not in bound:
                    sys.exit(f"qemu-profile: a block at 0x{start:x} ran with no listing")
                bound[handle][1] += 1
            elif line.startswith("Stopped"):
                m = stopped_re.match(line)
                if m and m.group(1) in bound:
                    bound[m.group(1)][1] -= 1
            elif line.startswith("IN:"):
                listing = []
                reading = True
            elif reading:
                m = insn_re.match(line)
                if m:
                    listing.append(int(m.group(1), 16))
    os.remove(log)
    for entry in bound.values():
        settle(entry)
    # The innermost (inlined) function of every executed instruction.
    pcs = sorted(per_pc)
    symbolizer = shutil.which("llvm-symbolizer")
    names = {}
    lines = {}
    if symbolizer:
        query = "".join(f"0x{pc:x}\n" for pc in pcs)
        out = subprocess.run([symbolizer, "--obj", args.elf, "--inlines", "--demangle",
                              "--output-style=LLVM"], input=query, capture_output=True,
                             text=True, check=True).stdout
        for pc, chunk in zip(pcs, out.split("\n\n")):
            first = chunk.strip().splitlines()[:2]
            if first:
                where = source_name(first[1]) if len(first) > 1 else ""
                names[pc] = f"{short(first[0])}  ({where.split(':')[0]})"
                lines[pc] = where
    table = symbols(args.elf)
    addresses = [a for a, _ in table]
    per_function = collections.Counter()
    for pc, n in per_pc.items():
        if pc in names:
            name = names[pc]
        else:
            i = bisect.bisect_right(addresses, pc) - 1
            name = short(table[i][1]) if i >= 0 else hex(pc)
        per_function[name] += n
    total = sum(per_function.values())
    print(f"{total:>12,}  instructions in all")
    for name, n in per_function.most_common(args.top):
        print(f"{n:>12,}  {100.0 * n / total:5.1f} %  {name}")
    if args.files:
        per_file = collections.Counter()
        for pc, n in per_pc.items():
            per_file[lines.get(pc, "?").split(":")[0]] += n
        print("by source file:")
        for where, n in per_file.most_common(args.top):
            print(f"{n:>12,}  {100.0 * n / total:5.1f} %  {where}")
    if args.outer:
        per_symbol = collections.Counter()
        for pc, n in per_pc.items():
            i = bisect.bisect_right(addresses, pc) - 1
            per_symbol[short(table[i][1]) if i >= 0 else hex(pc)] += n
        print("by function symbol (inlined code counted in its caller):")
        for name, n in per_symbol.most_common(args.top):
            print(f"{n:>12,}  {100.0 * n / total:5.1f} %  {name}")
    if args.inside:
        per_inner = collections.Counter()
        per_callee = collections.Counter()
        for pc, n in per_pc.items():
            i = bisect.bisect_right(addresses, pc) - 1
            if i >= 0 and args.inside in table[i][1]:
                per_inner[lines.get(pc, "?")] += n
                per_callee[names.get(pc, "?")] += n
        print(f"by inlined function, within function symbols matching '{args.inside}':")
        for name, n in per_callee.most_common(args.top):
            print(f"{n:>12,}  {name}")
        print(f"by source line, within function symbols matching '{args.inside}':")
        for where, n in per_inner.most_common(args.top):
            print(f"{n:>12,}  {where}")
    if args.annotate:
        objdump = shutil.which("llvm-objdump")
        out = subprocess.run([objdump, "-d", "--no-show-raw-insn", "--demangle",
                              os.path.abspath(args.elf)], capture_output=True, text=True,
                             check=True).stdout
        inside = False
        for line in out.splitlines():
            # Mapping symbols (`<$d...>`, `<$t...>`: data such as jump
            # tables, then code again) are labels inside a function.
            if line.endswith(">:") and "<$" not in line:
                inside = args.annotate in line
                if inside:
                    print(line)
            elif inside and ":" in line:
                try:
                    pc = int(line.split(":")[0].strip(), 16)
                except ValueError:
                    continue
                print(f"{per_pc.get(pc, 0):>10,} {line}")
    if args.mix:
        print_mix(args, per_pc, table, addresses, total)
    if args.lines:
        per_line = collections.Counter()
        for pc, n in per_pc.items():
            if args.lines in names.get(pc, ""):
                per_line[lines[pc]] += n
        print(f"by line, in functions matching '{args.lines}':")
        for where, n in per_line.most_common(args.top):
            print(f"{n:>12,}  {where}")
        hot = [(n, pc) for pc, n in per_pc.items() if args.lines in names.get(pc, "")]
        print("hottest instructions:")
        for n, pc in sorted(hot, reverse=True)[: args.top]:
            print(f"{n:>12,}  0x{pc:08x}  {lines.get(pc, '')}")


# Kinds of Thumb-2 instructions, by mnemonic prefix (after the stack's own
# loads and stores, which are told by their `sp` operand).
KINDS = [
    ("other loads", ("ldr", "ldm")),
    ("other stores", ("str", "stm")),
    ("multiplies, divides", ("mul", "mla", "mls", "smul", "smla", "umul", "umla", "umaal",
                             "sdiv", "udiv", "smmul", "smmla", "smuad", "smlad")),
    ("compares", ("cmp", "cmn", "tst", "teq")),
    ("IT blocks", ("it",)),
    ("branches", ("b", "cbz", "cbnz", "tbb", "tbh")),
    ("moves", ("mov", "mvn")),
]


def kind_of(text):
    """The kind of one disassembled instruction (`mnemonic operands`)."""
    mnemonic = text.split()[0] if text.split() else ""
    if re.search(r"\[sp[],]", text) or (mnemonic in ("push", "pop", "push.w", "pop.w")):
        return "stack loads, stores"
    for kind, prefixes in KINDS:
        # `bic`, `bfi`, `bfc` are bit operations, not branches.
        if mnemonic.startswith(prefixes) and not mnemonic.startswith(("bic", "bfi", "bfc")):
            return kind
    return "other arithmetic, logic"


def print_mix(args, per_pc, table, addresses, total):
    """The executed instructions by kind: in all, then per function symbol
    (inlined code in its caller) for the `--top` largest."""
    objdump = shutil.which("llvm-objdump")
    out = subprocess.run([objdump, "-d", "--no-show-raw-insn", os.path.abspath(args.elf)],
                         capture_output=True, text=True, check=True).stdout
    text_of = {}
    for line in out.splitlines():
        head, _, rest = line.partition(":")
        try:
            pc = int(head.strip(), 16)
        except ValueError:
            continue
        text_of[pc] = rest.strip()
    in_all = collections.Counter()
    per_symbol = collections.defaultdict(collections.Counter)
    for pc, n in per_pc.items():
        kind = kind_of(text_of.get(pc, ""))
        in_all[kind] += n
        i = bisect.bisect_right(addresses, pc) - 1
        per_symbol[short(table[i][1]) if i >= 0 else hex(pc)][kind] += n
    print("by kind of instruction:")
    for kind, n in in_all.most_common():
        print(f"{n:>12,}  {100.0 * n / total:5.1f} %  {kind}")
    largest = sorted(per_symbol.items(), key=lambda kv: -sum(kv[1].values()))[: args.top]
    print("stack loads and stores per function symbol (inlined code counted in its caller):")
    for name, kinds in largest:
        n = sum(kinds.values())
        stack = kinds["stack loads, stores"]
        print(f"{n:>12,}  {100.0 * stack / n:5.1f} % of them stack loads, stores  {name}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""128-bit arithmetic executed per step, from qemu traces of the perf drivers.

Usage: wide_per_step.py <elf_n> <pcs_n> <pcs_0> <steps> <target>

<pcs_n> and <pcs_0> are "count address" lines (uniq -c of the executed
program counters) of the driver run with <steps> cycles and with none; <elf_n>
is the first driver, linked against a flight library built with -g (the perf
presets: -g changes no instruction). Each executed address is mapped to its
chain of inlined functions (addr2line -i); an instruction counts as 128-bit
when any function of its chain works on fixedpoint/wide.hpp's U128 (its
return type or a parameter is U128, or it is one of the helpers that build
one from 64-bit words; a template argument alone does not count). Prints one line for perf_report.sh, with the functions that executed
128-bit instructions when there are any (issue 15 asks for none per cycle).
"""
import collections
import subprocess
import sys

# Helpers whose demangled signature does not name U128 but which build one.
U128_BUILDERS = (
    "sinkwatch::fx::wide::mul_full(unsigned long long, unsigned long long)",
    "sinkwatch::fx::wide::sum_partial_products(",
    "sinkwatch::fx::wide::mul_full_skipping_zero_words(",
    "sinkwatch::fx::wide::make_u128(",
)


def histogram(path):
    counts = collections.Counter()
    with open(path, encoding="ascii") as f:
        for line in f:
            count, pc = line.split()
            counts[int(pc, 16)] += int(count)
    return counts


def without_template_arguments(name):
    """The name with every <...> removed: a function parameterised by the
    wide type (fx::detail::mul_magnitudes<Out, U128, Shift>) whose own
    operands are 64-bit is not 128-bit code; its return type and parameters
    say whether it is."""
    out, depth = [], 0
    for c in name:
        if c == "<":
            depth += 1
        elif c == ">" and depth > 0:
            depth -= 1
        elif depth == 0:
            out.append(c)
    return "".join(out)


def is_wide(frame):
    return ("U128" in without_template_arguments(frame)) or any(frame.startswith(b) for b in U128_BUILDERS)


def wide_frames(elf, addresses):
    """{address: its outermost 128-bit frame and the function it is in} for
    the 128-bit ones."""
    result = {}
    chunk = 4000
    for start in range(0, len(addresses), chunk):
        batch = addresses[start:start + chunk]
        # One marker address after each real one splits the inline chains.
        args = []
        for a in batch:
            args += [hex(a), "0xfffffff0"]
        out = subprocess.run(["arm-none-eabi-addr2line", "-f", "-i", "-C", "-e", elf] + args,
                             capture_output=True, text=True, check=True).stdout.split("\n")
        frames, index = [], 0
        for i in range(0, len(out) - 1, 2):
            name = out[i]
            frames.append(name)
            if name == "??" and out[i + 1].startswith("??:0"):
                # The marker: the chain of batch[index] is complete.
                chain = frames[:-1]
                wide = [f for f in chain if is_wide(f)]
                if wide:
                    result[batch[index]] = f"{wide[-1]}  in  {chain[-1]}"
                frames, index = [], index + 1
    return result


def main():
    elf, pcs_n, pcs_0, steps, target = sys.argv[1:6]
    steps = int(steps)
    with_steps = histogram(pcs_n)
    without = histogram(pcs_0)
    executed = sorted(a for a in with_steps if with_steps[a] != without.get(a, 0))
    wide = wide_frames(elf, executed)
    per_function = collections.Counter()
    for a, frame in wide.items():
        per_function[frame] += with_steps[a] - without.get(a, 0)
    total = sum(per_function.values())
    print(f"wide_instructions_per_step target={target} impl=fixed value={total // steps} "
          "(128-bit arithmetic, fixedpoint/wide.hpp's U128)")
    for frame, count in per_function.most_common(8):
        print(f"  {count // steps:8d}  {frame[:300]}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Worst-case stack depth of firmware entry points, from GCC's call graph.

Reads every *.ci file (-fcallgraph-info=su) under a build directory, joins the
graphs across translation units by symbol name, and prints for each entry
point the deepest path: the sum of the frames along it. A cycle (recursion)
or a frame of dynamic size makes the bound unknown, and the script fails.
Calls into the C runtime (libgcc's __aeabi_* helpers, memcpy) have no .ci
file; they are listed with the allowance docs/firmware.md justifies.
"""
import re
import sys
from pathlib import Path

# Frames of the runtime helpers the flight code may call, in bytes. libgcc's
# ARM helpers are leaf routines that push at most a handful of registers
# (measured on the disassembly of libgcc.a from gcc-arm-none-eabi 12.2).
RUNTIME_ALLOWANCE = 64

# GCC names the target of a call through a function pointer __indirect_call.
# The flight code has one kind: the parameter table's extension validator.
# Its possible targets are listed in flight/firmware/indirect_targets.txt and
# the deepest of them is charged; an indirect call with no listed target makes
# the bound unknown.
INDIRECT = '__indirect_call'

NODE = re.compile(r'^node: \{ title: "([^"]*)" label: "([^"]*)"')
EDGE = re.compile(r'^edge: \{ sourcename: "([^"]*)" targetname: "([^"]*)"')
FRAME = re.compile(r'\\n(\d+) bytes \(([a-z,]+)\)')


def symbol(title):
    return title.rsplit(':', 1)[-1]


def load(build_dir):
    frames, qualifiers, labels, calls = {}, {}, {}, {}
    for ci in Path(build_dir).rglob('*.ci'):
        if 'CMakeFiles/3.' in str(ci):
            continue
        for line in ci.read_text().splitlines():
            m = NODE.match(line)
            if m:
                name = symbol(m.group(1))
                f = FRAME.search(m.group(2))
                if f:
                    frames[name] = int(f.group(1))
                    qualifiers[name] = f.group(2)
                    labels[name] = m.group(2).split('\\n', 1)[0]
                continue
            m = EDGE.match(line)
            if m:
                calls.setdefault(symbol(m.group(1)), set()).add(symbol(m.group(2)))
    return frames, qualifiers, labels, calls


def load_indirect_targets():
    path = Path(__file__).resolve().parent.parent / 'flight' / 'firmware' / 'indirect_targets.txt'
    if not path.exists():
        return []
    return [l.strip() for l in path.read_text().splitlines() if l.strip() and not l.startswith('#')]


def worst(entry, frames, qualifiers, calls):
    """(bytes, path, problems) of the deepest call chain from entry."""
    memo = {}
    problems = set()
    indirect_targets = load_indirect_targets()

    def visit(name, stack):
        if name in stack:
            problems.add('recursion through ' + name)
            return 0, [name]
        if name in memo:
            return memo[name]
        if name == INDIRECT:
            known = [t for t in indirect_targets if t in frames]
            if not known:
                problems.add('indirect call with no known target')
                return 0, [name]
            return max((visit(t, stack) for t in known), key=lambda d: d[0])
        if name not in frames:
            memo[name] = (RUNTIME_ALLOWANCE, [name + ' (runtime allowance)'])
            return memo[name]
        if qualifiers[name] != 'static':
            problems.add('%s frame is %s' % (name, qualifiers[name]))
        best = (0, [])
        for callee in sorted(calls.get(name, ())):
            depth = visit(callee, stack | {name})
            if depth[0] > best[0]:
                best = depth
        memo[name] = (frames[name] + best[0], [name] + best[1])
        return memo[name]

    total, path = visit(entry, frozenset())
    return total, path, problems


def main():
    if len(sys.argv) < 3:
        sys.exit('usage: stack_report.py BUILD_DIR TARGET_NAME [ENTRY_SYMBOL ...]')
    build_dir, target = sys.argv[1], sys.argv[2]
    entries = sys.argv[3:] or ['main']
    frames, qualifiers, labels, calls = load(build_dir)
    failed = False
    for entry in entries:
        if entry not in frames:
            print('stack_worst_case target=%s entry=%s value=unknown (no frame found)' % (target, entry))
            failed = True
            continue
        total, path, problems = worst(entry, frames, qualifiers, calls)
        print('stack_worst_case target=%s entry=%s value=%d' % (target, labels.get(entry, entry), total))
        print('  deepest path: ' + ' > '.join(labels.get(p, p) for p in path))
        for p in sorted(problems):
            print('  UNBOUNDED: ' + p)
            failed = True
    sys.exit(1 if failed else 0)


if __name__ == '__main__':
    main()

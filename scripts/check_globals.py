#!/usr/bin/env python3
"""Fails when a rayspace library defines a writable data symbol that the allowlist does not name.

Settings travel in rayspace::Settings (rayspace/settings.h), never in process-wide variables. A
data symbol in a writable section (.bss, .data and their thread-local .tbss, .tdata; not the
read-only-after-relocation .data.rel.ro) is either process-wide mutable state or a table initialised
at run time; the allowlist names each one and says why.

  check_globals.py [--allowlist FILE] [--no-stale] ARCHIVE...

Exit 0: every symbol is allowed (and, unless --no-stale, every allowlist line matches a symbol);
exit 1: a symbol is not allowed, or an allowlist line is stale; exit 2: bad arguments or nm failed.
"""
import argparse
import os
import re
import subprocess
import sys

WRITABLE = re.compile(r"^\.(bss|data|tbss|tdata)(\.|$)(?!rel\.ro)")

# The compiler's and the runtime's, and third-party headers' own: not rayspace's state.
IGNORED = [
    re.compile(r"^std::__ioinit$"),
    re.compile(r"^DW\.ref\."),
    re.compile(r"^(guard variable|typeinfo|vtable|VTT) "),
    re.compile(r"^\.L"),
    re.compile(r"^__"),
    # Statics the standard library's, CLI11's, CGAL's, Boost's and nlohmann-json's headers define in
    # every library that uses them.
    re.compile(r"^(std|CLI|CGAL|boost|nlohmann)::"),
]


def read_allowlist(path):
    """[(library regex, symbol regex, line number, text)] from lines 'LIBRARY SYMBOL-REGEX'."""
    entries = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            parts = text.split(None, 1)
            if len(parts) != 2:
                sys.exit(f"check_globals: {path}:{n}: expected 'LIBRARY SYMBOL-REGEX', got '{text}'")
            try:
                entries.append((re.compile(parts[0]), re.compile(parts[1]), n, text))
            except re.error as e:
                print(f"check_globals: {path}:{n}: bad regular expression: {e}", file=sys.stderr)
                sys.exit(2)
    return entries


def writable_symbols(archive):
    try:
        out = subprocess.run(["nm", "-C", "--defined-only", "--format=sysv", archive], check=True, capture_output=True,
                             text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"check_globals: nm {archive}: {e}", file=sys.stderr)
        sys.exit(2)
    symbols = set()
    for line in out.splitlines():
        fields = line.split("|")  # name|value|class|type|size|line|section; a name may hold '|'
        if len(fields) < 7 or fields[-4].strip() not in ("OBJECT", "TLS"):
            continue
        name, section = "|".join(fields[:-6]).strip(), fields[-1].strip()
        if WRITABLE.match(section) and not any(p.search(name) for p in IGNORED):
            symbols.add(name)
    return symbols


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--allowlist", default=os.path.join(here, "writable_globals.txt"))
    ap.add_argument("--no-stale", action="store_true", help="do not fail on allowlist lines that match nothing")
    ap.add_argument("archives", nargs="+")
    args = ap.parse_args()
    entries = read_allowlist(args.allowlist)
    used = set()
    bad = []
    for archive in args.archives:
        if not os.path.isfile(archive):
            print(f"check_globals: no such library: {archive}", file=sys.stderr)
            return 2
        lib = os.path.basename(archive)
        for sym in sorted(writable_symbols(archive)):
            hit = [e for e in entries if e[0].search(lib) and e[1].search(sym)]
            if hit:
                used.update(e[2] for e in hit)
            else:
                bad.append(f"{lib}: writable data symbol not in the allowlist: {sym}")
    stale = [] if args.no_stale else [f"{args.allowlist}:{e[2]}: matches no symbol: {e[3]}" for e in entries if e[2] not in used]
    for line in bad + stale:
        print(line)
    if bad:
        print(f"check_globals: {len(bad)} writable symbol(s) outside {args.allowlist}: settings belong in "
              "rayspace::Settings (rayspace/settings.h); a table or a process resource gets an allowlist line with its reason")
    if bad or stale:
        return 1
    print(f"check_globals: {len(args.archives)} libraries, every writable data symbol allowed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Markdown tables of a `rayspace mutate --report` file, as docs/verification.md shows them.

Prints the per-file score table (equivalent mutants split into those the optimiser proved and those
argued in the survivors list) and every mutant that survived or was argued equivalent, by class, with
its source line and reason. With --rerun, the verdicts of later targeted runs (`--only ID...`) replace
the full run's for the same mutant ids.

    python3 scripts/mutation_table.py docs/verification/full-run.json [--rerun RERUN.json ...]
"""
import argparse
import json
import sys
from collections import defaultdict


def passes_cell(passes):
    return ", ".join(passes[:3]) + (", ..." if len(passes) > 3 else "")


def load(path):
    try:
        with open(path) as f:
            return json.load(f)["mutants"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        sys.exit(f"mutation_table.py: {path}: not a mutate report ({e})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("report", help="the JSON file `rayspace mutate --report` wrote")
    ap.add_argument("--rerun", action="append", default=[], help="a later report whose mutants replace the same ids")
    args = ap.parse_args()
    mutants = load(args.report)
    by_id = {m["id"]: i for i, m in enumerate(mutants)}
    for path in args.rerun:
        for m in load(path):
            if m["id"] not in by_id:
                sys.exit(f"mutation_table.py: {path}: mutant {m['id']} is not in {args.report}")
            mutants[by_id[m["id"]]] = m

    rows = defaultdict(lambda: defaultdict(int))
    passes = {}
    for m in mutants:
        r = rows[m["file"]]
        r["mutants"] += 1
        status = m["status"]
        if status == "equivalent":
            status = "argued" if "class" in m else "proved"
        r[status] += 1
        passes[m["file"]] = m.get("passes", [])

    print("| file | passes | mutants | killed | survived, not equivalent | equivalent (proved + argued) | score |")
    print("|---|---|---:|---:|---:|---:|---:|")
    total = defaultdict(int)
    for file in sorted(rows):
        r = rows[file]
        for k, v in r.items():
            total[k] += v
        k, s = r["killed"], r["survived"]
        score = f"{100 * k / (k + s):.0f} %" if k + s else "-"
        print(f"| `{file}` | {passes_cell(passes[file])} | {r['mutants']} | {k} | {s} | {r['proved']} + {r['argued']} | {score} |")
    k, s = total["killed"], total["survived"]
    print(f"| **all** | | **{total['mutants']}** | **{k}** | **{s}** | **{total['proved']} + {total['argued']}** | "
          f"**{100 * k / max(k + s, 1):.1f} %** |")
    other = {x: total[x] for x in ("stillborn", "invalid") if total[x]}
    if other:
        print("\nAlso: " + ", ".join(f"{v} {x}" for x, v in other.items()) + " (not scored).")

    by_class = defaultdict(list)
    for m in mutants:
        if m["status"] == "survived" or (m["status"] == "equivalent" and "class" in m):
            by_class[m.get("class", "unexplained")].append(m)
    for cls in sorted(by_class, key=lambda c: (c == "equivalent", c)):
        print(f"\n**{cls}** ({len(by_class[cls])})\n")
        for m in sorted(by_class[cls], key=lambda m: m["id"]):
            print(f"- `{m['id']}` — `{m.get('source', '')}`: {m.get('why', 'not explained')}")


if __name__ == "__main__":
    main()

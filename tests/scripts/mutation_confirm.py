#!/usr/bin/env python3
"""scripts/mutation_check.py --tiers: a full-only kill stands only when its failing tests fail again
on the mutant and pass without it; the rerun names exactly the failing tests, whatever their names hold."""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import mutation_check as mc  # noqa: E402

failures = []


def expect(what, got, want):
    if got != want:
        failures.append(f"{what}: got {got!r}, want {want!r}")


calls = []


def fake_run(cmd, cwd, timeout=None):
    calls.append(cmd)
    return fake_run.codes.pop(0), ""


mc.run = fake_run
args = type("Args", (), {"jobs": 2})()
failed = ["cli.mutate.configs (Failed)", "fused path: lanes (scalar, AVX2) give [x]'s pairs (Timeout)"]

# The rerun's -R pattern matches each failing test's whole name and nothing else.
fake_run.codes = [8]
mc.run_named(args, "b", failed)
pattern = calls[-1][calls[-1].index("-R") + 1]
for name in ("cli.mutate.configs", "fused path: lanes (scalar, AVX2) give [x]'s pairs"):
    expect(f"pattern matches '{name}'", bool(re.fullmatch(pattern, name)), True)
for other in ("cli.mutate.configsX", "cliXmutate.configs", "fused path: lanes scalar, AVX2 give x's pairs"):
    expect(f"pattern matches '{other}'", bool(re.fullmatch(pattern, other)), False)

# Failed again on the mutant, passes without it: a kill.
fake_run.codes = [0]
expect("again failed, restored passes", mc.confirmed(args, "b", failed, 8), ("full", failed))
# Passed on the mutant when run again: not a kill (and the restored copy is not run).
fake_run.codes = []
expect("passed on the mutant again", mc.confirmed(args, "b", failed, 0), ("unconfirmed", failed))
# Failed without the mutant too: the test fails here whatever the source, not a kill.
fake_run.codes = [8]
expect("fails without the mutant", mc.confirmed(args, "b", failed, 8), ("unconfirmed", failed))

# A report's full-only kill from before confirmation comes back to be confirmed; a confirmed one stays.
entry = mc.entry(("emu/src/a.cpp", 3, 0, 1, "-", "+ to -"), "full", failed)
expect("a new full-only kill is marked confirmed", entry.get("confirmed"), True)
import json  # noqa: E402
import tempfile  # noqa: E402

with tempfile.TemporaryDirectory() as tmp:
    report = os.path.join(tmp, "r.json")
    old = dict(entry)
    del old["confirmed"]
    with open(report, "w", encoding="utf-8") as f:
        json.dump({"seed": 1, "count": 2, "source_commit": "c", "mutants": [
            old, dict(entry, line=4), dict(entry, line=5, result="default")]}, f)
    r_args = type("Args", (), {"report": report, "seed": 1, "count": 2})()
    done = {k[1]: v[0] for k, v in mc.resumed(r_args, "c").items()}
    expect("resumed results by line", done, {3: "full?", 4: "full", 5: "default"})

if failures:
    print("mutation_confirm:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("mutation_confirm: a full-only kill is confirmed twice; a failure that does not repeat, or repeats unmutated, is not a kill")

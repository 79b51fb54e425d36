#!/usr/bin/env python3
"""Every registered test carries exactly one tier label (default or full) and a TIMEOUT.

Reads `ctest --show-only=json-v1` of a build tree, so it sees the doctest cases discovered after the
build as ctest will run them. Prints each test that breaks the rule and the tiers' sizes.
Usage: check_tiers.py CTEST BUILD_DIR
Exit: 0 every test is in one tier with a timeout, 1 otherwise, 2 usage or ctest failure.
"""
import json
import subprocess
import sys

TIERS = {"default", "full"}


def main():
    if len(sys.argv) != 3:
        sys.stderr.write("usage: check_tiers.py CTEST BUILD_DIR\n")
        return 2
    ctest, build = sys.argv[1:]
    run = subprocess.run([ctest, "--test-dir", build, "--show-only=json-v1"], capture_output=True, text=True)
    if run.returncode != 0:
        sys.stderr.write(f"check_tiers: ctest --show-only failed: {run.stderr.strip()}\n")
        return 2
    tests = json.loads(run.stdout)["tests"]
    problems = []
    counts = {tier: 0 for tier in TIERS}
    for test in tests:
        props = {p["name"]: p["value"] for p in test.get("properties", [])}
        tiers = [label for label in props.get("LABELS", []) if label in TIERS]
        if len(tiers) != 1:
            problems.append(f"{test['name']}: tier labels {tiers or 'none'}, expected one of default, full")
        else:
            counts[tiers[0]] += 1
        if not props.get("TIMEOUT"):
            problems.append(f"{test['name']}: no TIMEOUT")
    for line in problems:
        print(line)
    print(f"{len(tests)} tests: {counts['default']} default, {counts['full']} full, {len(problems)} problems")
    return 1 if problems or not tests else 0


if __name__ == "__main__":
    sys.exit(main())

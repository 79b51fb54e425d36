#!/usr/bin/env python3
"""Mutation check of the emulator's C++ sources: do the fast unit tests notice a planted bug?

Picks a seeded sample of mutants over emu/ (relational operators <, <=, >, >=, ==, != swapped for
their neighbour; + and - swapped; && and || swapped; an integer constant off by one; a statement
dropped; two plain arguments of a call swapped), applies each one alone to a copy of the source tree,
rebuilds the unit tests there (ccache makes that one translation unit and a link), and runs a ctest
subset with a timeout. A mutant is killed when a test fails or times out, survives when every test
passes, and is stillborn when it does not compile (not counted in the score). Prints killed and
survived per pass (the source file decides the pass) and every survivor with file:line and the
mutation. The original file is restored after each mutant whatever happens (an exception, Ctrl-C or
SIGTERM): with --build the mutants go into the source tree that build was configured from; without
it into a copy under --work, configured and built once first.

The same seed, count and sources give the same mutants: every pass's candidate sites, shuffled by
the seed, are taken in turn, so a small sample still reaches every pass. `--dry-run` lists them without building anything.

With --tiers it measures the test tiers' power instead (docs/verification.md, "Test tiers"): the
sample is drawn over emu/, gpu/src, verify/, app/, frame/, diff/, export/ and accuracy/ (--count) and the kernels gpu/shaders/*.comp
(--kernels), the copy is built whole with the project's configuration (Release, Vulkan), and each
mutant runs the default tier (`ctest -L default --stop-on-failure`) and, only when the default tier
misses it, the full tier's other tests: killed by the default tier, by the full tier only, survived
or stillborn. The default tier's kill list must contain the full suite's: no mutant killed by the
full tier only. A tier whose only failures are timeouts runs once more before it counts as a kill (a
loaded machine is not a test that noticed the bug). The report is written after every mutant, with
the failing tests that killed it. A full-only kill is confirmed: its failing tests run again on the
mutant (they must fail) and on the restored copy (they must pass); otherwise it is 'unconfirmed',
neither a kill nor a survivor (a test that failed under load). `--resume` with the same --report goes on where a stopped run left
off, in the same copy (its source commit must match the report's), or, where there is no copy under
--work (another checkout), in a copy made from the report's source commit, whose unmutated default
tier runs first. A file named PAUSE in --work holds the run before its next mutant until it is removed.

Usage: mutation_check.py [--seed N] [--count N] [--tests REGEX] [--exclude REGEX] [--files PATH ...]
                         [--source DIR] [--build DIR | --work DIR] [--timeout SEC] [--jobs N]
                         [--cmake-arg ARG ...] [--report JSON] [--dry-run] [--tiers [--kernels N] [--resume]]
Exit: 0 when the run completed (survivors are a result, not an error), 2 on a usage error.
"""
import argparse
import contextlib
import glob
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import time

# The fast emulator unit tests (doctest names; no Vulkan, no CLI): the known-answer tests of every
# pass and the frame-level checks that run in seconds.
DEFAULT_TESTS = ("^(raster|surfaces|raygen|trim|hash|sort|compress|decompress|build|cone|traverse|reduce|reduction|"
                 "intersect|shade|resolve|IntPow|objects tree|tree|known answer|workgroup|hard case|hit convention|"
                 "frame|determinism)")
# The frame-level and randomized sweeps that take tens of seconds each: left out of every mutant's run.
DEFAULT_EXCLUDE = ("^(objects tree: fused rounds|objects tree: the same frame digest|intersect simd: many rays|"
                   "determinism: hierarchy digests|traverse.compact mirror: random calls)")
# The passes' sources; a mutated header rebuilds every file that includes it, so headers are opt-in.
DEFAULT_FILES = ("emu/src/*.cpp",)
# --tiers: the emulator, the Vulkan host code, the verifier, the command line and the commands' engines
# (frame, diff, export; the accuracy study); and the kernels apart. A resumed run lists them in its copy of the tree.
TIER_FILES = ("emu/src/*.cpp", "gpu/src/*.cpp", "verify/src/*.cpp", "app/*.cpp", "frame/src/*.cpp", "diff/src/*.cpp",
              "export/src/*.cpp", "accuracy/src/*.cpp")
KERNEL_FILES = ("gpu/shaders/*.comp",)

# Source file stem -> the pass its code serves (docs/mutation.md); files serving every pass are "shared".
PASS_OF_STEM = {
    "raster": "raster", "raster_detail": "raster", "surfaces": "surfaces", "surface_math": "surfaces",
    "raygen": "raygen", "raygen_math": "raygen", "trim": "trim", "hash": "hash", "hash_math": "hash",
    "sort": "compress/sort/decompress", "build": "build", "cone": "build", "spheres": "build",
    "traverse": "traverse", "cone_simd": "traverse", "reduce": "reduce", "traverse_fused": "traverse.compact",
    "traverse_compact_wg": "traverse.compact", "intersect": "intersect", "intersect_simd": "intersect",
    "tree": "tree", "tree_calls": "tree", "tree_streams": "tree", "object_tree_traverse": "tree", "shade": "shade",
    "shade_math": "shade", "resolve": "resolve",
}

# (name, pattern, replacement): one mutation of one match. Operators need spaces around them, which
# the sources' formatting gives binary operators and never template brackets or shifts.
OPERATOR_SWAPS = [
    ("< to <=", r"(?<=\s)<(?=\s)", "<="), ("<= to <", r"(?<=\s)<=(?=\s)", "<"),
    ("> to >=", r"(?<=\s)>(?=\s)", ">="), (">= to >", r"(?<=\s)>=(?=\s)", ">"),
    ("== to !=", r"(?<=\s)==(?=\s)", "!="), ("!= to ==", r"(?<=\s)!=(?=\s)", "=="),
    ("+ to -", r"(?<=\s)\+(?=\s)", "-"), ("- to +", r"(?<=\s)-(?=\s)", "+"),
    ("&& to ||", r"(?<=\s)&&(?=\s)", "||"), ("|| to &&", r"(?<=\s)\|\|(?=\s)", "&&"),
]
CONSTANT = re.compile(r"(?<![\w.])(\d+)(u|U)?(?![\w.'])")
SWAP_ARGS = re.compile(r"\b(\w+)\((\w+), (\w+)\)")
STATEMENT = re.compile(r"^\s*[\w\[\]().>-]+\s*(\+=|-=|\*=|=|\+\+|--)[^=].*;\s*$|^\s*[\w.>-]+\+\+;\s*$")


def pass_of(path):
    stem = os.path.splitext(os.path.basename(path))[0]
    if path.startswith("gpu/shaders/"):
        return "kernel " + stem
    if not path.startswith("emu/"):
        return path.split("/")[0] + ("/src" if path.startswith("gpu/src/") else "")
    return PASS_OF_STEM.get(stem, "shared")


def code_lines(text):
    """Yields (line number, line) for lines that are code: no comments, preprocessor or asserts."""
    in_block = False
    for n, line in enumerate(text.split("\n"), 1):
        s = line.strip()
        if in_block:
            in_block = "*/" not in s
            continue
        if s.startswith("/*"):
            in_block = "*/" not in s
            continue
        if not s or s.startswith(("//", "#", "static_assert", "RS_CHECK", "assert")):
            continue
        yield n, line.split("//")[0]


def line_mutants(path, n, line):
    out = []
    for name, pattern, repl in OPERATOR_SWAPS:
        for m in re.finditer(pattern, line):
            out.append((path, n, m.start(), m.end(), repl, name))
    for m in CONSTANT.finditer(line):
        if '"' in line[:m.start()] and '"' in line[m.end():]:
            continue  # inside a string
        out.append((path, n, m.start(1), m.end(1), str(int(m.group(1)) + 1), f"{m.group(1)} to {int(m.group(1)) + 1}"))
    for m in SWAP_ARGS.finditer(line):
        if m.group(2) != m.group(3):
            out.append((path, n, m.start(2), m.end(3), f"{m.group(3)}, {m.group(2)}",
                        f"{m.group(1)}({m.group(2)}, {m.group(3)}) to {m.group(1)}({m.group(3)}, {m.group(2)})"))
    if STATEMENT.match(line) and not re.match(r"^\s*(const|auto|std::|for|if|return|using|\w+\s+\w+\s*=)", line):
        body = line.rstrip()
        out.append((path, n, len(line) - len(line.lstrip()), len(body), "", f"statement dropped: {body.strip()}"))
    return out


def all_mutants(source, files):
    mutants = []
    for rel in files:
        with open(os.path.join(source, rel), encoding="utf-8") as f:
            text = f.read()
        for n, line in code_lines(text):
            mutants.extend(line_mutants(rel, n, line))
    return sorted(mutants)


def draw(candidates, count, seed):
    """Every pass gets its turn: each pass's candidates shuffled by the seed, taken round-robin."""
    rng = random.Random(seed)
    by_pass = {}
    for m in candidates:
        by_pass.setdefault(pass_of(m[0]), []).append(m)
    queues = [by_pass[p] for p in sorted(by_pass)]
    for q in queues:
        rng.shuffle(q)
    sample = []
    while len(sample) < count and any(queues):
        for q in queues:
            if q and len(sample) < count:
                sample.append(q.pop())
    return sorted(sample)


def apply(text, mutant):
    _, n, start, end, repl, _ = mutant
    lines = text.split("\n")
    line = lines[n - 1]
    lines[n - 1] = line[:start] + repl + line[end:]
    return "\n".join(lines)


def run(cmd, cwd, timeout=None):
    try:
        p = subprocess.run(["nice"] + cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                           text=True)
        return p.returncode, p.stdout
    except subprocess.TimeoutExpired:
        return None, "timeout"


def source_commit(source):
    """The source's commit, with '+dirty' when its tracked files differ from it."""
    def git(*a):
        p = subprocess.run(["git", "-C", source] + list(a), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        return p.stdout.strip() if p.returncode == 0 else ""
    head = git("rev-parse", "HEAD") or "unknown"
    return head + ("+dirty" if git("status", "--porcelain", "--untracked-files=no") else "")


def configured_copy(args, refresh=False):
    """Copies the source tree (without build folders) to WORK/src and configures WORK/src/build. With
    `refresh` an existing copy's sources are replaced (its build folder kept for an incremental build)."""
    src = os.path.join(args.work, "src")
    skip = shutil.ignore_patterns("build", "build-*", ".git", "out")
    if refresh and os.path.isdir(src):
        for name in os.listdir(src):
            if name != "build":
                path = os.path.join(src, name)
                shutil.rmtree(path) if os.path.isdir(path) and not os.path.islink(path) else os.remove(path)
    if refresh or not os.path.isdir(src):
        shutil.copytree(args.source, src, ignore=skip, symlinks=True, dirs_exist_ok=True)
        with open(os.path.join(src, ".source_commit"), "w", encoding="utf-8") as f:
            f.write(source_commit(args.source) + "\n")
    build = os.path.join(src, "build")
    os.makedirs(build, exist_ok=True)
    restore_pending(src)
    # Compiler-cache entries keyed on paths relative to the copy, as scripts/build.sh does for a clone:
    # the copy's first build reuses the checkout's objects.
    os.environ["CCACHE_BASEDIR"] = os.path.abspath(src)
    # Ninja, as scripts/build.sh uses it, unless the copy's build was made with another generator.
    generator = ["-G", "Ninja"] if shutil.which("ninja") and not os.path.exists(os.path.join(build, "CMakeCache.txt")) else []
    rc, out = run(["cmake", ".."] + generator + args.cmake_arg, build)
    if rc != 0:
        sys.exit(f"mutation_check.py: configuring the copy failed:\n{out}")
    return src, build


def prepare_copy(args):
    """The copy's unit tests built; the fast tests must pass unmutated."""
    src, build = configured_copy(args)
    rc, out = run(["cmake", "--build", ".", f"-j{args.jobs}", "--target", "rayspace_tests"], build)
    if rc != 0:
        sys.exit(f"mutation_check.py: the unmutated copy does not build:\n{out[-3000:]}")
    rc, out = ctest(args, build, [])
    if rc != 0:
        sys.exit(f"mutation_check.py: the unmutated copy fails its tests:\n{out[-3000:]}")
    return src, build


def prepare_tiers(args, baseline_tiers):
    """The copy built whole with the project's configuration; the tiers in `baseline_tiers` must pass
    unmutated (both for a new run; none when resumed in the copy where the report says they passed;
    the default tier in a copy made anew from the report's commit, whose full tier the report vouches
    for: a machine that cannot run the tests fails the default tier too)."""
    src = os.path.join(args.work, "src")
    build = os.path.join(src, "build")
    rc, out = run(["cmake", "--build", ".", f"-j{args.jobs}"], build)
    if rc != 0:
        sys.exit(f"mutation_check.py: the unmutated copy does not build:\n{out[-3000:]}")
    if baseline_tiers:
        for tier in baseline_tiers:
            t0 = time.time()
            rc, failed = tier_run(args, build, tier)
            if rc != 0:
                sys.exit(f"mutation_check.py: the unmutated copy fails its {tier} tier: {', '.join(failed) or rc}")
            print(f"unmutated: the {tier} tier passed in {time.time() - t0:.0f} s", flush=True)
    return src, build


# "	183 - cone simd: lanes (all of them) equal the scalar path (Failed)": a doctest name holds spaces
# and parentheses; the reason is the last parenthesised group of the line.
FAILED_TEST = re.compile(r"^\s*\d+ - (.+) \(([^()]+)\)[ \t]*$", re.M)


def failed_tests(out):
    """The tests ctest's output lists as failed, as 'name (reason)'."""
    tail = out.split("The following tests FAILED:")[-1] if "The following tests FAILED:" in out else ""
    return [f"{name} ({why})" for name, why in FAILED_TEST.findall(tail)]


def tier_run(args, build, tier):
    """One tier with --stop-on-failure: (exit code, the failing tests as 'name (reason)'). A run whose
    failures are all timeouts runs again, and its second verdict stands."""
    for attempt in (1, 2):
        # Without the timing data of earlier runs ctest starts in test order, the unit tests first,
        # so a killed mutant stops early.
        cost = os.path.join(build, "Testing", "Temporary", "CTestCostData.txt")
        if os.path.exists(cost):
            os.remove(cost)
        rc, out = run(["ctest", "-L", f"^{tier}$", f"-j{args.jobs}", "--stop-on-failure"], build)
        failed = failed_tests(out)
        if rc == 0 or not failed or any(not f.endswith("(Timeout)") for f in failed) or attempt == 2:
            return rc, failed
        print(f"    only timeouts ({', '.join(failed)}): the {tier} tier once more", flush=True)


PENDING = ".mutant_pending.json"


def restore_pending(src):
    """A run killed outright (SIGKILL) leaves its mutant in the copy; the original saved beside it
    is written back before anything else runs there."""
    pending = os.path.join(src, PENDING)
    if os.path.exists(pending):
        with open(pending, encoding="utf-8") as f:
            saved = json.load(f)
        with open(os.path.join(src, saved["file"]), "w", encoding="utf-8") as f:
            f.write(saved["original"])
        os.remove(pending)
        print(f"restored {saved['file']} from a run that stopped mid-mutant", flush=True)


@contextlib.contextmanager
def mutated(src, mutant, after=None):
    """The mutant written into its file for the block; the original restored whatever happens, then
    `after()` (a rebuild of the restored file)."""
    path = os.path.join(src, mutant[0])
    with open(path, encoding="utf-8") as f:
        original = f.read()
    pending = os.path.join(src, PENDING)
    with open(pending, "w", encoding="utf-8") as f:
        json.dump({"file": mutant[0], "original": original}, f)
    try:
        with open(path, "w", encoding="utf-8") as f:
            f.write(apply(original, mutant))
        yield
    finally:
        with open(path, "w", encoding="utf-8") as f:
            f.write(original)
        os.remove(pending)
        if after:
            after()


def try_mutant_tiers(args, src, build, mutant):
    """(result, the failing tests that killed it)."""
    build_all = ["cmake", "--build", ".", f"-j{args.jobs}"]
    # The restored file is rebuilt before the next mutant's tests: its unity batch is another's too.
    with mutated(src, mutant, after=lambda: run(build_all, build)):
        if run(build_all, build)[0] != 0:
            return "stillborn", []
        rc, failed = tier_run(args, build, "default")
        if rc != 0:
            return "default", failed
        rc, failed = tier_run(args, build, "full")
        if rc == 0:
            return "survived", []
        again = run_named(args, build, failed)
    return confirmed(args, build, failed, again)


def reconfirmed(args, src, build, mutant, failed):
    """A full-only kill of a report written before kills were confirmed, confirmed now."""
    build_all = ["cmake", "--build", ".", f"-j{args.jobs}"]
    with mutated(src, mutant, after=lambda: run(build_all, build)):
        if run(build_all, build)[0] != 0:
            return "stillborn", []
        again = run_named(args, build, failed)
    return confirmed(args, build, failed, again)


def run_named(args, build, failed):
    """Reruns exactly the tests `failed` names: their exit code."""
    names = [f.rsplit(" (", 1)[0] for f in failed]
    pattern = "^(" + "|".join(re.sub(r"([][.^$*+?(){}|\\])", r"\\\1", n) for n in names) + ")$"
    return run(["ctest", "-R", pattern, f"-j{args.jobs}"], build)[0]


# A full-only kill is the claim that the default tier misses a bug: it stands only when the killing
# tests fail again on the mutant and pass on the restored copy under the same load.
def confirmed(args, build, failed, again):
    """'full' when the killing tests failed twice on the mutant and pass without it; 'unconfirmed'
    (neither a kill nor a survivor, listed) otherwise."""
    if again == 0:
        print(f"    {', '.join(failed)}: passed on the mutant when run again", flush=True)
        return "unconfirmed", failed
    if run_named(args, build, failed) != 0:
        print(f"    {', '.join(failed)}: failed without the mutant too", flush=True)
        return "unconfirmed", failed
    return "full", failed


def wait_while_paused(args):
    """--tiers: a file PAUSE in --work holds the run between mutants (the machine wanted for a timed
    run); removing it lets the run go on."""
    pause = os.path.join(args.work, "PAUSE") if args.tiers else None
    if pause and os.path.exists(pause):
        print(f"paused: {pause} exists", flush=True)
        while os.path.exists(pause):
            time.sleep(5)


def print_tiers(results):
    killed_default = [m for m, r in results if r == "default"]
    killed_full = [m for m, r in results if r in ("default", "full")]
    print(f"{'group':<26} {'default':>7} {'full only':>9} {'survived':>8} {'stillborn':>9} {'unconfirmed':>11}")
    for g in sorted({pass_of(m[0]) for m, _ in results}) + ["all"]:
        rows = [r for m, r in results if g == "all" or pass_of(m[0]) == g]
        print(f"{g:<26} {rows.count('default'):>7} {rows.count('full'):>9} {rows.count('survived'):>8} "
              f"{rows.count('stillborn'):>9} {rows.count('unconfirmed'):>11}")
    print(f"\nkilled by the default tier: {len(killed_default)}; by the full suite: {len(killed_full)}")
    for label, wanted in (("killed by the full tier only", "full"), ("survivors", "survived"),
                          ("unconfirmed: a full-tier failure that did not repeat on the mutant, or repeated without it", "unconfirmed")):
        listed = [m for m, r in results if r == wanted]
        print(f"{label} ({len(listed)}):")
        for m in listed:
            print(f"  {describe(m)}")


def ctest(args, build, extra):
    cmd = ["ctest", "-R", args.tests, f"-j{args.jobs}", "--timeout", str(args.timeout)] + extra
    if args.exclude:
        cmd += ["-E", args.exclude]
    return run(cmd, build, timeout=args.timeout * 4)


def try_mutant(args, src, build, mutant):
    with mutated(src, mutant):
        rc, _ = run(["cmake", "--build", ".", f"-j{args.jobs}", "--target", "rayspace_tests"], build)
        if rc != 0:
            return "stillborn"
        rc, _ = ctest(args, build, ["--stop-on-failure"])
        return "survived" if rc == 0 else "killed"


def describe(m):
    return f"{m[0]}:{m[1]}: {m[5]}"


def print_table(results):
    passes = sorted({pass_of(m[0]) for m, _ in results})
    print(f"{'pass':<26} {'killed':>6} {'survived':>8} {'stillborn':>9} {'score':>6}")
    for p in passes + ["all"]:
        rows = [r for m, r in results if p == "all" or pass_of(m[0]) == p]
        k, s, b = rows.count("killed"), rows.count("survived"), rows.count("stillborn")
        score = f"{100 * k / (k + s):.0f}%" if k + s else "-"
        print(f"{p:<26} {k:>6} {s:>8} {b:>9} {score:>6}")
    survivors = [m for m, r in results if r == "survived"]
    print(f"\nsurvivors ({len(survivors)}):")
    for m in survivors:
        print(f"  {describe(m)}")


class OneLineParser(argparse.ArgumentParser):
    """A usage error is one line on stderr naming the argument, and exit code 2."""

    def error(self, message):
        sys.stderr.write(f"mutation_check.py: {message}\n")
        sys.exit(2)


def parse_args(argv):
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = OneLineParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=40)
    ap.add_argument("--tests", default=DEFAULT_TESTS, help="ctest -R regex (the fast unit tests by default)")
    ap.add_argument("--exclude", default=DEFAULT_EXCLUDE, help="ctest -E regex ('' runs every test --tests matches)")
    ap.add_argument("--files", nargs="+", default=None, help="sources to mutate, relative to --source (globs)")
    ap.add_argument("--source", default=here)
    ap.add_argument("--build", default=None, help="a configured build of --source: mutate in place, restoring each file")
    ap.add_argument("--work", default=None, help="scratch folder for the copy (default SOURCE/build/mutation)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds per test")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cmake-arg", action="append", default=None)
    ap.add_argument("--report", default=None, help="write every mutant and its result as JSON")
    ap.add_argument("--dry-run", action="store_true", help="list the sampled mutants; build nothing")
    ap.add_argument("--tiers", action="store_true", help="measure the test tiers: default tier, then full tier if missed")
    ap.add_argument("--kernels", type=int, default=20, help="--tiers: kernel mutants (gpu/shaders/*.comp) besides --count")
    ap.add_argument("--resume", action="store_true", help="--tiers: go on with the --report of a stopped run, in its copy")
    args = ap.parse_args(argv)
    if args.kernels < 0:
        ap.error(f"--kernels {args.kernels}: must be at least 0")
    if args.count < 1:
        ap.error(f"--count {args.count}: must be at least 1")
    if args.timeout < 1 or args.jobs < 1:
        ap.error("--timeout and --jobs must be at least 1")
    for flag, value in (("--tests", args.tests), ("--exclude", args.exclude)):
        try:
            re.compile(value)
        except re.error as e:
            ap.error(f"{flag} '{value}': not a regular expression ({e})")
    if args.tiers and args.build:
        ap.error("--tiers builds its own copy (--work): --build is not used with it")
    if args.resume and not (args.tiers and args.report):
        ap.error("--resume goes on with a --tiers run's --report: give both")
    if args.build and not os.path.isfile(os.path.join(args.build, "CMakeCache.txt")):
        ap.error(f"--build '{args.build}': not a configured build (no CMakeCache.txt)")
    files_given = args.files is not None
    args.file_patterns = args.files or (TIER_FILES if args.tiers else DEFAULT_FILES)
    args.kernel_patterns = () if files_given else KERNEL_FILES
    files = []
    for pattern in args.file_patterns:
        found = listed(args.source, [pattern])
        if not found:
            ap.error(f"--files '{pattern}': no such source under {args.source}")
        files.extend(found)
    args.files = sorted(set(files))
    args.work = args.work or os.path.join(args.source, "build", "mutation")
    if args.tiers:
        args.kernel_files = listed(args.source, args.kernel_patterns)
        data = os.path.join(os.path.dirname(os.path.abspath(args.source)), "shared", "scenes")
        args.cmake_arg = args.cmake_arg or ["-DCMAKE_BUILD_TYPE=Release", "-DRAYSPACE_VULKAN=ON",
                                            f"-DRAYSPACE_TEST_DATA_ROOT={data}"]
    args.cmake_arg = args.cmake_arg or ["-DCMAKE_BUILD_TYPE=RelWithDebInfo", "-DRAYSPACE_VULKAN=OFF"]
    return args


def listed(root, patterns):
    """The files under `root` the glob patterns name, relative to it, sorted."""
    return sorted({os.path.relpath(p, root) for pattern in patterns for p in glob.glob(os.path.join(root, pattern))})


def sample_of(args, source):
    candidates = all_mutants(source, args.files)
    sample = draw(candidates, args.count, args.seed)
    print(f"seed {args.seed}: {len(sample)} of {len(candidates)} mutants over {len(args.files)} files")
    if args.tiers and args.kernel_files and args.kernels:
        kernel_candidates = all_mutants(source, args.kernel_files)
        kernels = draw(kernel_candidates, args.kernels, args.seed)
        print(f"seed {args.seed}: {len(kernels)} of {len(kernel_candidates)} kernel mutants over {len(args.kernel_files)} kernels")
        sample = sample + kernels
    return sample


def entry(m, r, failed):
    e = {"file": m[0], "line": m[1], "pass": pass_of(m[0]), "mutation": m[5], "result": r, "killed_by": failed}
    if r in ("full", "unconfirmed"):
        e["confirmed"] = r == "full"
    return e


def write_report(args, commit, results):
    """Written whole after every mutant, through a temporary file: a stopped run leaves a readable report."""
    if not args.report:
        return
    tmp = args.report + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump({"seed": args.seed, "count": args.count, "kernels": args.kernels if args.tiers else 0,
                   "tests": "tiers" if args.tiers else args.tests, "source_commit": commit, "baseline": "passed",
                   "mutants": [entry(m, r, failed) for m, r, failed in results]}, f, indent=1)
    os.replace(tmp, args.report)


def usage_error(message):
    sys.stderr.write(f"mutation_check.py: {message}\n")
    sys.exit(2)


def resumed(args, commit):
    """The results of the report a stopped run left, keyed by (file, line, mutation)."""
    try:
        with open(args.report, encoding="utf-8") as f:
            report = json.load(f)
    except (OSError, ValueError) as e:
        usage_error(f"--resume: cannot read --report '{args.report}': {e}")
    if report.get("source_commit") != commit or report.get("seed") != args.seed or report.get("count") != args.count:
        usage_error(f"--resume: --report '{args.report}' is of another run (source {report.get('source_commit')}, "
                 f"seed {report.get('seed')}, count {report.get('count')}; this copy: {commit}, seed {args.seed}, count {args.count})")
    # A full-only kill from before kills were confirmed comes back as 'full?': confirmed on resume.
    return {(e["file"], e["line"], e["mutation"]): (e["result"] + ("?" if e["result"] == "full" and "confirmed" not in e else ""),
                                                    e.get("killed_by", [])) for e in report["mutants"]}


def copy_of_reported_commit(args):
    """--resume in another checkout (a fresh clone, the report kept in the repository): the copy is
    made anew from the report's source commit, whose unmutated tiers the report says passed."""
    try:
        with open(args.report, encoding="utf-8") as f:
            commit = json.load(f).get("source_commit", "")
    except (OSError, ValueError) as e:
        usage_error(f"--resume: cannot read --report '{args.report}': {e}")
    if not re.fullmatch(r"[0-9a-f]{40}", commit):
        usage_error(f"--resume: no copy under --work '{args.work}', and the report's source '{commit}' is not a clean commit to make one from")
    src = os.path.join(args.work, "src")
    archive = subprocess.run(["git", "-C", args.source, "archive", commit], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    if archive.returncode != 0:
        usage_error(f"--resume: the report's source commit {commit} is not in {args.source}: {archive.stderr.decode().strip()}")
    # A copy left without its marker (a run stopped while copying) is not added to: made whole anew.
    shutil.rmtree(src, ignore_errors=True)
    os.makedirs(src)
    untar = subprocess.run(["tar", "-x", "-C", src], input=archive.stdout, stderr=subprocess.PIPE)
    if untar.returncode != 0:
        usage_error(f"--resume: unpacking {commit} under {src} failed: {untar.stderr.decode().strip()}")
    with open(os.path.join(src, ".source_commit"), "w", encoding="utf-8") as f:
        f.write(commit + "\n")
    print(f"resuming: a copy of {commit[:12]} made under {src}; its unmutated default tier runs first", flush=True)


def main(argv):
    args = parse_args(argv)
    if args.dry_run:
        for m in sample_of(args, args.source):
            print(f"  [{pass_of(m[0])}] {describe(m)}")
        return 0
    done = {}
    if args.tiers:
        # The sample is drawn from the copy, so the run (and a resumed one) mutates the sources it was
        # drawn from whatever happens to the checkout meanwhile.
        marker = os.path.join(args.work, "src", ".source_commit")
        # A copy made here from the report's commit has not yet passed its default tier unmutated:
        # this machine's data and tools may differ from the run's before.
        fresh_copy = args.resume and not os.path.exists(marker)
        if fresh_copy:
            copy_of_reported_commit(args)
        if args.resume:
            with open(marker, encoding="utf-8") as f:
                done = resumed(args, f.read().strip())
        src, build = configured_copy(args, refresh=not args.resume)
        with open(marker, encoding="utf-8") as f:
            commit = f.read().strip()
        # The files too come from the copy: the checkout may have gained or lost some since.
        args.files = listed(src, args.file_patterns)
        args.kernel_files = listed(src, args.kernel_patterns)
        sample = sample_of(args, src)
        baseline = ("default",) if fresh_copy else () if args.resume else ("default", "full")
        src, build = prepare_tiers(args, baseline)
        # The unmutated tiers passed: a report from here on lets --resume skip them.
        if not args.resume:
            write_report(args, commit, [])
    else:
        commit = source_commit(args.source)
        sample = sample_of(args, args.source)
        if args.build:
            restore_pending(args.source)
        src, build = (args.source, args.build) if args.build else prepare_copy(args)
    # SIGTERM unwinds like Ctrl-C, so the mutated file is restored.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    results = []
    for i, m in enumerate(sample, 1):
        key = (m[0], m[1], m[5])
        if key in done and done[key][0] == "full?":
            wait_while_paused(args)
            r, failed = reconfirmed(args, src, build, m, done[key][1])
            results.append((m, r, failed))
            write_report(args, commit, results)
            print(f"[{i}/{len(sample)}] {r:<9} {describe(m)} (the report's full-only kill, confirmed again)", flush=True)
            continue
        if key in done:
            results.append((m,) + done[key])
            print(f"[{i}/{len(sample)}] {done[key][0]:<9} {describe(m)} (from the report)", flush=True)
            continue
        wait_while_paused(args)
        t0 = time.time()
        r, failed = try_mutant_tiers(args, src, build, m) if args.tiers else (try_mutant(args, src, build, m), [])
        results.append((m, r, failed))
        write_report(args, commit, results)
        print(f"[{i}/{len(sample)}] {r:<9} {describe(m)} ({time.time() - t0:.0f} s){' ' + failed[0] if failed else ''}", flush=True)
    print()
    if args.tiers:
        print_tiers([(m, r) for m, r, _ in results])
    else:
        print_table([(m, r) for m, r, _ in results])
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

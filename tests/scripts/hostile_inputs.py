#!/usr/bin/env python3
"""Hostile input against every command: malformed scenes, meshes and saved calls, bad flag values,
output paths that point elsewhere. Each case runs the CLI in a fresh working directory with its own
TMPDIR and XDG_CACHE_HOME, under a timeout, and must:

  - end by itself (no hang) and not by a signal (no crash);
  - exit 2 with one line on stderr, "rayspace: error: ...", when the case is bad input ("bad"),
    or exit 0 or 2 when the value may be valid ("either"); never 1 (an internal failure) for a
    user's mistake;
  - write nothing but the outputs it names, and leave its TMPDIR empty.

Usage: hostile_inputs.py --rayspace EXE --src SOURCE_DIR --work DIR [--jobs N] [--list] [--only REGEX]
Exit: 0 every case held, 1 some did not (each named with what it did), 2 bad arguments.
"""
import argparse
import concurrent.futures
import copy
import gzip
import json
import os
import re
import shutil
import signal
import subprocess
import sys

TIMEOUT = 60  # seconds; the slowest case (a 64x64 diff) takes about 3

CAMERA = {"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45}
BASE = {
    "name": "hostile",
    "camera": CAMERA,
    "image": {"width": 8, "height": 8},
    "lights": [{"position": [0, 4, 4], "intensity": 1.0}],
    "materials": {"m": {"diffuse": [0.8, 0.8, 0.8], "reflectivity": 0.2}},
    "objects": [{"generator": "box", "material": "m", "transform": {"translate": [0, 0, 0]}}],
    "max_depth": 1,
}
TRIANGLE_OBJ = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"

# Values that are wrong for most fields; for some a value is valid, so these cases accept 0 or 2.
BAD_VALUES = [None, "x", [], {}, -1, 0, 1e39, -1e39, True, [1, 2], [1, 2, 3, 4], "NaN", [None, 0, 0],
              ["1", 0, 0], 2**64, -2**63, 1e-45, [1e308, 0, 0]]
FIELDS = [
    ("camera", "eye"), ("camera", "target"), ("camera", "up"), ("camera", "fov_y_deg"), ("image", "width"),
    ("image", "height"), ("lights", 0, "position"), ("lights", 0, "intensity"), ("lights", 0, "attenuation"),
    ("lights", 0, "shape"), ("lights", 0, "radius"), ("lights", 0, "samples"), ("materials", "m", "diffuse"),
    ("materials", "m", "reflectivity"), ("materials", "m", "transparency"), ("materials", "m", "ior"),
    ("objects", 0, "generator"), ("objects", 0, "params"), ("objects", 0, "material"),
    ("objects", 0, "transform", "translate"), ("objects", 0, "transform", "scale"),
    ("objects", 0, "transform", "rotate_deg"), ("objects", 0, "instances"), ("objects", 0, "mesh"),
    ("max_depth",), ("name",), ("camera",), ("lights",), ("objects",), ("materials",),
]


def set_path(doc, path, value):
    d = doc
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value


class Case:
    def __init__(self, name, args, expect="bad", files=None, outputs=(), needle=None):
        self.name = name            # unique, says what is hostile
        self.args = args            # the CLI's arguments ({cwd} is the case's working directory)
        self.expect = expect        # "bad": exit 2; "either": exit 0 or 2
        self.files = files or {}    # name -> bytes or str, written into the working directory first
        self.outputs = set(outputs)  # names the run may create in its working directory
        self.needle = needle        # text stderr must hold when the case is refused


def scene_text(doc):
    return json.dumps(doc)


def scene_cases():
    cases = []
    for path in FIELDS:
        for i, value in enumerate(BAD_VALUES):
            doc = copy.deepcopy(BASE)
            set_path(doc, path, value)
            label = ".".join(str(p) for p in path)
            cases.append(Case(f"scene {label} = {json.dumps(value)[:30]}", ["render", "s.json", "--out", "o.png"],
                              "either", {"s.json": scene_text(doc)}, ("o.png",)))
    return cases


def raw_json_cases():
    good = scene_text(BASE)
    texts = {
        "empty file": "",
        "only whitespace": "   \n\t",
        "a bare number": "42",
        "an array": "[1, 2, 3]",
        "a string": '"scene"',
        "truncated in a key": good[: good.index('"camera"') + 4],
        "truncated at the half": good[: len(good) // 2],
        "trailing comma": good[:-1] + ",}",
        "two documents": good + good,
        "a NUL byte after the closing brace": good + "\0",
        "a NUL byte inside a string": good.replace('"hostile"', '"host\0ile"'),
        "a key given twice": good[:-1] + ', "max_depth": 2}',
        "nested 100,000 deep": '{"camera": ' + "[" * 100000 + "]" * 100000 + "}",
        "nested 300 deep in objects": good[:-1] + ', "x": ' + '{"a":' * 300 + "1" + "}" * 300 + "}",
        "a number that overflows a double": good.replace("45", "1e400"),
        "a negative zero size": good.replace('"width": 8', '"width": -0'),
        "a fractional size": good.replace('"width": 8', '"width": 8.5'),
        "a size beyond the limit": good.replace('"width": 8', '"width": 100000'),
        "comments": "// a scene\n" + good,
        "invalid UTF-8 in a string": good.replace('"hostile"', '"\udcff"'),
        "an unknown top-level key": good[:-1] + ', "cameras": {}}',
        "a byte order mark": "\ufeff" + good,
        "control characters in the name": good.replace('"hostile"', '"a\\u0001b"'),
        "a 20-digit integer": good.replace('"width": 8', '"width": 123456789012345678901'),
    }
    cases = []
    for what, text in texts.items():
        data = text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text
        # Some of these are valid JSON with a valid scene (a BOM is not): refused or rendered, never 1.
        expect = "either" if what in ("a byte order mark", "control characters in the name") else "bad"
        cases.append(Case(f"scene text: {what}", ["render", "s.json", "--out", "o.png"], expect, {"s.json": data},
                          ("o.png",)))
    return cases


def mesh_cases():
    objs = {
        "an empty OBJ": "",
        "a face index 0": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
        "a face index past the vertices": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
        "a negative index past the start": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n",
        "a NaN coordinate": "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "an infinite coordinate": "v inf 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "a coordinate beyond 2^62": "v 1e30 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "a vertex with two coordinates": "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "a face with two vertices": "v 0 0 0\nv 1 0 0\nf 1 2\n",
        "a face index that is not a number": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n",
        "a NUL byte": "v 0 0 0\0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "binary junk": "".join(chr(i) for i in range(1, 256)) * 8,
        "a missing mtllib": "mtllib nowhere.mtl\n" + TRIANGLE_OBJ,
        "an mtllib that is a directory": "mtllib .\n" + TRIANGLE_OBJ,
        "an index of 2^40": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1099511627776\n",
        "a degenerate triangle only": "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n",
    }
    cases = []
    for what, text in objs.items():
        doc = copy.deepcopy(BASE)
        doc["objects"] = [{"name": "m", "mesh": "m.obj"}]
        expect = "either" if what in ("a missing mtllib", "a degenerate triangle only") else "bad"
        cases.append(Case(f"mesh: {what}", ["render", "s.json", "--out", "o.png"], expect,
                          {"s.json": scene_text(doc), "m.obj": text.encode("latin-1")}, ("o.png",)))
    plys = {
        "a PLY without end_header": "ply\nformat ascii 1.0\nelement vertex 3\n",
        "a PLY with more vertices declared than given": "ply\nformat ascii 1.0\nelement vertex 9\nproperty float x\n"
                                                        "property float y\nproperty float z\nelement face 0\n"
                                                        "property list uchar int vertex_indices\nend_header\n0 0 0\n",
        "a binary PLY cut short": "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                  "property float y\nproperty float z\nend_header\n\x00\x00",
        "a PLY with an unknown format": "ply\nformat ebcdic 1.0\nend_header\n",
        "a PLY face list of 255 indices": "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                          "end_header\n0 0 0\n255" + " 0" * 255 + "\n",
    }
    for what, text in plys.items():
        doc = copy.deepcopy(BASE)
        doc["objects"] = [{"name": "m", "mesh": "m.ply"}]
        expect = "either" if what == "a PLY face list of 255 indices" else "bad"  # degenerate, not malformed
        cases.append(Case(f"mesh: {what}", ["render", "s.json", "--out", "o.png"], expect,
                          {"s.json": scene_text(doc), "m.ply": text.encode("latin-1")}, ("o.png",)))
    gz = {
        "a .obj.gz that is not gzip": TRIANGLE_OBJ.encode(),
        "a .obj.gz cut short": gzip.compress(TRIANGLE_OBJ.encode() * 1000)[:100],
        "a .obj.gz of NUL bytes": gzip.compress(b"\0" * (4 << 20)),
        "an empty .obj.gz": b"",
    }
    for what, data in gz.items():
        doc = copy.deepcopy(BASE)
        doc["objects"] = [{"name": "m", "mesh": "m.obj.gz"}]
        cases.append(Case(f"mesh: {what}", ["render", "s.json", "--out", "o.png"], "bad",
                          {"s.json": scene_text(doc), "m.obj.gz": data}, ("o.png",)))
    return cases


def cli_cases(src):
    scene = os.path.join(src, "scenes", "cornell-mirrors.json")
    good = {"s.json": scene_text(BASE)}
    bad_render = [
        ["--size", "0x8"], ["--size", "8x0"], ["--size", "-8x8"], ["--size", "8"], ["--size", "axb"],
        ["--size", "99999x8"], ["--size", "8x8x8"], ["--size", ""], ["--threads", "0"], ["--threads", "-1"],
        ["--threads", "100000"], ["--algo", "nope"], ["--algo", ""], ["--backend", "gpu"], ["--device", "99"],
        ["--path", "sideways"], ["--objects", "some"], ["--levels", "0"], ["--levels", "99"], ["--levels", "x"],
        ["--subdivision", "0"], ["--subdivision", "3"], ["--bounces", "-1"], ["--bounces", "99"],
        ["--pair-capacity", "0"], ["--reduction", "magic"], ["--schedule", "sideways"], ["--schedule", "random:x"],
        ["--out", "o.xyz"], ["--out", "nodir/o.png"], ["--out", ""], ["--out", "."], ["--out", "/dev/full"],
        ["--stats", "nodir/s.json"], ["--stats", "o.png"], ["--stats", "s.json"], ["--kernel", "reduce"],
        ["--kernel", "nosuch=x.comp"], ["--kernel", "reduce=missing.comp"], ["--backend", "emu", "--kernel", "reduce=s.json"],
        ["--data", "nodir"], ["--grid-cells", "0"], ["--grid-area", "1x1"], ["--split-bytes", "1"],
        ["--max-groups", "0"], ["--local-size", "0"], ["--local-size", "2000"], ["--faithful", "nope"],
        ["--bogus"], ["--size"],
    ]
    cases = []
    for extra in bad_render:
        args = ["render", "s.json", "--out", "o.png"] + extra
        if "--out" in extra:
            args = ["render", "s.json"] + extra
        cases.append(Case(f"render {' '.join(extra) or '(empty)'}", args, "bad", good, ()))
    bad_diff = [
        ["--inject", "nosuch:1"], ["--inject", "trim:999"], ["--inject", "trim:2"], ["--inject-each", ","],
        ["--inject-each", "trim:1,nope"], ["--path", "fused", "--inject", "reduce:subgroup-32"],
        ["--path", "fused", "--kernel", "reduce=" + os.path.join(src, "gpu", "shaders", "reduce.comp")],
        ["--compare", "loose"], ["--report", "nodir/r.json"], ["--save-inputs", "nodir/calls"],
        ["--save-inputs", "s.json"], ["--size", "0x0"], ["--local-size", "4096"], ["--device", "-5"],
    ]
    for extra in bad_diff:
        cases.append(Case(f"diff {' '.join(extra)}", ["diff", "s.json", "--size", "16x16"] + extra, "bad", good, ()))
    others = [
        ("replay of a missing directory", ["replay", "nodir"]),
        ("replay of a file", ["replay", "s.json"]),
        ("replay of an empty directory", ["replay", "empty"]),
        ("export of a missing directory", ["export", "nodir", "--out", "x"]),
        ("export without --out", ["export", "nodir"]),
        ("export into a file", ["export", "empty", "--out", "s.json"]),
        ("accuracy with 1 sample", ["accuracy", "s.json", "--samples", "1"]),
        ("accuracy into a missing parent", ["accuracy", "s.json", "--out", "nodir/acc"]),
        ("bench with no configurations", ["bench", "s.json", "--configs", ""]),
        ("bench with an unknown configuration", ["bench", "s.json", "--configs", "nope"]),
        ("bench with a bad size", ["bench", "s.json", "--sizes", "8x"]),
        ("bench with zero repetitions", ["bench", "s.json", "--repetitions", "0"]),
        ("bench into a missing directory", ["bench", "s.json", "--json", "nodir/b.json"]),
        ("shadow-bench with a bad size", ["shadow-bench", "s.json", "--size", "0x0"]),
        ("data check without a root", ["data", "check", "--data", "nodir"]),
        ("data check of an unknown scene", ["data", "check", "nosuch", "--data", "."]),
        ("mutate with a bad regex", ["mutate", scene, "--only", "("]),
        ("mutate with a negative limit", ["mutate", scene, "--limit", "-1"]),
        ("mutate with a file as --work", ["mutate", scene, "--work", "s.json"]),
        ("mutate with an unknown pass", ["mutate", scene, "--pass", "nosuch"]),
        ("mutate with a garbage survivors file", ["mutate", scene, "--survivors", "s.json"]),
        ("reproduce with an unknown table", ["reproduce", "--table", "nosuch"]),
        ("devices with a bad device", ["devices", "--device", "77"]),
        ("simulate of a missing directory", ["simulate", "nodir"]),
        ("simulate of a file", ["simulate", "s.json"]),
        ("simulate of a directory without sequence.txt", ["simulate", "empty"]),
        ("simulate with subgroups of 0", ["simulate", "empty", "--subgroup-size", "0"]),
        ("simulate with subgroups of 129", ["simulate", "empty", "--subgroup-size", "129"]),
        ("diff with unknown backends", ["diff", "s.json", "--size", "16x16", "--backends", "emu,gpu"]),
        ("diff with backends in the wrong order", ["diff", "s.json", "--size", "16x16", "--backends", "sim,emu"]),
        ("diff with a subgroup size on Vulkan", ["diff", "s.json", "--size", "16x16", "--backends", "emu,vulkan", "--subgroup-size", "4"]),
        ("diff with a subgroup size of 0", ["diff", "s.json", "--size", "16x16", "--backends", "emu,sim", "--subgroup-size", "0"]),
        ("render on an unknown backend", ["render", "s.json", "--backend", "simulator"]),
        ("an unknown command", ["frobnicate"]),
        ("no command", []),
        ("render of a missing scene", ["render", "nosuch.json"]),
        ("render of a directory", ["render", "."]),
        ("render of /dev/zero", ["render", "/dev/zero"]),
    ]
    for what, args in others:
        files = dict(good)
        files["empty/"] = None
        cases.append(Case(what, args, "bad", files, ()))
    # Reproducer directories whose sequence.txt lies: each refused naming the file and line.
    spirv = "kernels/k.spv"
    steps = {
        "a bad header": "rayspace-repro 2\n",
        "an unknown step": "rayspace-repro 1\nfrobnicate 0\n",
        "a buffer of a petabyte": "rayspace-repro 1\nbuffer 0 1000000000000000 x\n",
        "a buffer size that is no number": "rayspace-repro 1\nbuffer 0 12ab x\n",
        "a write into a missing buffer": "rayspace-repro 1\nwrite 3 inputs/w.bin 4\n",
        "a write larger than its file": "rayspace-repro 1\nbuffer 0 16 x\nwrite 0 inputs/w.bin 16\n",
        "a dispatch of a missing pipeline": "rayspace-repro 1\nbuffer 0 16 x\ndispatch 7 1 1 0 0\n",
        "a pipeline that is not SPIR-V": f"rayspace-repro 1\npipeline 0 k {spirv} 1 0 64 0\n",
        "a pipeline whose file is missing": "rayspace-repro 1\npipeline 0 k kernels/none.spv 1 0 64 0\n",
        "a read beyond its buffer": "rayspace-repro 1\nbuffer 0 4 x\nread 0 64 inputs/w.bin - 0 4\n",
        "a push word that is not hexadecimal": f"rayspace-repro 1\nbuffer 0 16 x\ndispatch 0 1 1 4 zz 0\n",
        "a step with too few fields": "rayspace-repro 1\nbuffer 0\n",
    }
    for what, text in steps.items():
        files = {"r/sequence.txt": text, "r/inputs/w.bin": b"\0\0\0\0", "r/kernels/k.spv": b"not spirv"}
        cases.append(Case(f"simulate of a reproducer with {what}", ["simulate", "r"], "bad", files, ()))
    return cases


def output_cases():
    cases = []
    for name in ["../escaped", "/tmp/abs-escaped", "", "..", ".", "a/b", "a\\b", "\x01x", "x" * 300]:
        doc = copy.deepcopy(BASE)
        doc["name"] = name
        cases.append(Case(f"scene name {json.dumps(name)[:20]} as the default output", ["render", "s.json"], "bad",
                          {"s.json": scene_text(doc)}, ()))
    doc = copy.deepcopy(BASE)
    cases.append(Case("--out and --stats one file by ./", ["render", "s.json", "--out", "o.png", "--stats", "./o.png"], "bad",
                      {"s.json": scene_text(doc)}, ()))
    cases.append(Case("--stats naming the scene", ["render", "s.json", "--out", "o.png", "--stats", "s.json"], "bad",
                      {"s.json": scene_text(doc)}, ()))
    return cases


def all_cases(src):
    cases = scene_cases() + raw_json_cases() + mesh_cases() + cli_cases(src) + output_cases()
    names = [c.name for c in cases]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise SystemExit(f"hostile_inputs.py: case names given twice: {sorted(dup)[:5]}")
    return cases


def run_case(exe, work, index, case):
    cwd = os.path.join(work, f"{index:04d}")
    shutil.rmtree(cwd, ignore_errors=True)
    os.makedirs(cwd)
    for name, data in case.files.items():
        path = os.path.join(cwd, name)
        if name.endswith("/"):
            os.makedirs(path, exist_ok=True)
            continue
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(data if isinstance(data, bytes) else data.encode("utf-8", "surrogateescape"))
    tmp = os.path.join(cwd, ".tmp")
    cache = os.path.join(cwd, ".cache")
    os.makedirs(tmp)
    os.makedirs(cache)
    before = set(os.listdir(cwd))
    env = dict(os.environ, TMPDIR=tmp, XDG_CACHE_HOME=cache)
    escaped = [os.path.join(work, "..", "escaped.png"), "/tmp/abs-escaped.png"]
    for p in escaped:
        if os.path.exists(p):
            os.remove(p)
    try:
        r = subprocess.run([exe] + case.args, cwd=cwd, env=env, capture_output=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return f"hung (no exit within {TIMEOUT} s)"
    problems = []
    err = r.stderr.decode("utf-8", "replace")
    if r.returncode < 0:
        problems.append(f"killed by signal {signal.Signals(-r.returncode).name}")
    elif case.expect == "bad" and r.returncode != 2:
        problems.append(f"exit {r.returncode}, expected 2")
    elif case.expect == "either" and r.returncode not in (0, 2):
        problems.append(f"exit {r.returncode}, expected 0 or 2")
    if r.returncode == 2:
        lines = err.splitlines()
        errors = [l for l in lines if l.startswith("rayspace: error: ") or l.startswith("rayspace: ") and "error" in l]
        if len(errors) != 1:
            problems.append(f"{len(errors)} error lines on stderr")
    after = set(os.listdir(cwd))
    written = sorted(after - before - case.outputs)
    if r.returncode != 0:
        written = sorted(after - before)
    if written:
        problems.append(f"wrote {written}")
    if os.listdir(tmp):
        problems.append(f"left in TMPDIR: {os.listdir(tmp)}")
    for p in escaped:
        if os.path.exists(p):
            problems.append(f"wrote {p}")
            os.remove(p)
    if problems:
        return "; ".join(problems) + f" (stderr: {err.strip()[:200]})"
    shutil.rmtree(cwd, ignore_errors=True)
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rayspace", required=True)
    ap.add_argument("--src", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--only", default="")
    args = ap.parse_args()
    if args.jobs < 1:
        ap.error("--jobs must be at least 1")
    try:
        only = re.compile(args.only)
    except re.error as e:
        ap.error(f"--only '{args.only}': not a regular expression ({e})")
    cases = [c for c in all_cases(args.src) if only.search(c.name)]
    if args.list:
        for c in cases:
            print(f"{c.expect:6} {c.name}")
        print(f"{len(cases)} cases")
        return 0
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_case, os.path.abspath(args.rayspace), os.path.abspath(args.work), i, c): c
                   for i, c in enumerate(cases)}
        for f in concurrent.futures.as_completed(futures):
            problem = f.result()
            if problem:
                failures.append(f"[{futures[f].name}] {problem}")
    for line in sorted(failures):
        print(line)
    print(f"hostile inputs: {len(cases) - len(failures)} of {len(cases)} cases held")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

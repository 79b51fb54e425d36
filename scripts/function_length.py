#!/usr/bin/env python3
"""Lists function definitions longer than a limit (80 lines) in the project's C++ sources.

A long function passes when a comment line starting `// Long:` gives the reason, either on the
function's first line or in the comment block directly above it (the line before the function, or a
`// Long:` line further up that block when the reason needs more than one line). Functions whose source
cannot carry the comment may be named in an allowlist (scripts/long_functions.txt): one line per
function, `path<TAB or spaces>qualified name<spaces>-- reason`. An allowlisted function that is no
longer long, or no longer exists, is an error too, so the list stays small and true.

Functions are found with libclang (Debian: python3-clang), parsing each translation unit with its
flags from the build's compile_commands.json; definitions in headers count once, where they are.
A function's length runs from its first line (the template line, for templates) to its closing
brace; lambdas count as part of the function that holds them.

Usage: function_length.py --build BUILD [--source SRC] [--max 80] [--allow FILE] [DIR ...]
       function_length.py --files FILE.cpp ... (no compile database: plain -std=c++20 parse; for the
       self-test fixture and quick checks)
Exit: 0 when every long function has a reason, 1 otherwise, 2 on a usage or environment error.
"""
import argparse
import json
import os
import shlex
import sys
from concurrent.futures import ThreadPoolExecutor


def import_clang():
    try:
        import clang.cindex as ci  # noqa: F401
    except ImportError:
        # A python3 that is not the system's (pyenv, venv) lacks Debian's dist-packages; the bindings
        # are pure Python over ctypes, so the system copy works from any 3.x.
        for p in ("/usr/lib/python3/dist-packages",):
            if os.path.isdir(os.path.join(p, "clang")) and p not in sys.path:
                sys.path.append(p)
        try:
            import clang.cindex as ci  # noqa: F401
        except ImportError:
            sys.stderr.write("function_length: the libclang Python bindings are missing (Debian: apt-get install "
                             "python3-clang; scripts/bootstrap.sh installs it)\n")
            sys.exit(2)
    import clang.cindex as ci
    return ci


ci = import_clang()

FUNCTION_KINDS = {
    ci.CursorKind.FUNCTION_DECL,
    ci.CursorKind.CXX_METHOD,
    ci.CursorKind.CONSTRUCTOR,
    ci.CursorKind.DESTRUCTOR,
    ci.CursorKind.CONVERSION_FUNCTION,
    ci.CursorKind.FUNCTION_TEMPLATE,
}
# Where definitions may sit (namespaces, classes, templates); function bodies are not searched.
CONTAINER_KINDS = {
    ci.CursorKind.TRANSLATION_UNIT,
    ci.CursorKind.NAMESPACE,
    ci.CursorKind.CLASS_DECL,
    ci.CursorKind.STRUCT_DECL,
    ci.CursorKind.UNION_DECL,
    ci.CursorKind.CLASS_TEMPLATE,
    ci.CursorKind.CLASS_TEMPLATE_PARTIAL_SPECIALIZATION,
    ci.CursorKind.UNEXPOSED_DECL,  # extern "C" { ... }
    ci.CursorKind.LINKAGE_SPEC,
}


def qualified_name(c):
    parts = [c.spelling]
    p = c.semantic_parent
    while p is not None and p.kind != ci.CursorKind.TRANSLATION_UNIT:
        if p.spelling:
            parts.append(p.spelling)
        elif p.kind == ci.CursorKind.NAMESPACE:
            parts.append("(anonymous)")
        p = p.semantic_parent
    return "::".join(reversed(parts))


def is_body_definition(c):
    if not c.is_definition():
        return False
    # `= default` / `= delete` and declarations without a body have no compound statement.
    return any(ch.kind == ci.CursorKind.COMPOUND_STMT for ch in c.get_children())


def walk(cursor, wanted, found):
    for c in cursor.get_children():
        loc = c.location
        if loc.file is None:
            continue
        path = os.path.realpath(loc.file.name)
        if c.kind in FUNCTION_KINDS:
            if wanted(path) and is_body_definition(c):
                start, end = c.extent.start.line, c.extent.end.line
                found[(path, start)] = (qualified_name(c), start, end)
            continue
        # Namespaces and classes reopened in a project file are cursors located in that file, so
        # system headers need no visit.
        if c.kind in CONTAINER_KINDS and wanted(path):
            walk(c, wanted, found)


def compile_args(entry, path):
    """The entry's flags without the compiler, the output and the source itself."""
    args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
    out, i = [], 1
    while i < len(args):
        a = args[i]
        i += 1
        if a == "-o":
            i += 1
        elif a != "-c" and os.path.realpath(os.path.join(entry.get("directory", ""), a)) != path:
            out.append(a)
    return out


def parse(path, args, wanted):
    index = ci.Index.create()
    try:
        tu = index.parse(path, args=args)  # with bodies: a definition's extent ends at its brace
    except ci.TranslationUnitLoadError:
        return path, {}, [f"cannot parse (missing or unreadable; reconfigure the build if it was removed)"]
    errors = [d for d in tu.diagnostics if d.severity >= ci.Diagnostic.Error]
    found = {}
    walk(tu.cursor, wanted, found)
    return path, found, errors


def reason_for(lines, start):
    """The `// Long:` reason on the function's first line or in the comment block above, or None."""
    first = lines[start - 1] if start - 1 < len(lines) else ""
    if "// Long:" in first:
        return first[first.index("// Long:"):]
    i = start - 2
    while i >= 0:
        s = lines[i].strip()
        if not s.startswith("//"):
            break
        if s.startswith("// Long:"):
            return s
        i -= 1
    return None


def read_allowlist(path, source):
    allowed = {}
    if not path:
        return allowed
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            if " -- " not in s:
                sys.stderr.write(f"{path}:{n}: expected 'path name -- reason'\n")
                sys.exit(2)
            head, reason = s.split(" -- ", 1)
            fields = head.split()
            if len(fields) != 2 or not reason.strip():
                sys.stderr.write(f"{path}:{n}: expected 'path name -- reason'\n")
                sys.exit(2)
            allowed[(os.path.realpath(os.path.join(source, fields[0])), fields[1])] = (n, reason.strip())
    return allowed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", help="build directory holding compile_commands.json")
    ap.add_argument("--source", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--max", type=int, default=80, help="longest function allowed without a reason (lines)")
    ap.add_argument("--allow", help="allowlist file (path name -- reason per line)")
    ap.add_argument("--files", nargs="+", help="parse these files alone (no compile database)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("dirs", nargs="*", default=["app", "core", "emu", "gpu/src", "verify", "refs"])
    a = ap.parse_args()
    source = os.path.realpath(a.source)

    if a.files:
        files = [(os.path.realpath(f), ["-x", "c++", "-std=c++20"]) for f in a.files]
        roots = [os.path.dirname(f) + os.sep for f, _ in files]
    else:
        if not a.build:
            ap.error("give --build (for compile_commands.json) or --files")
        db = os.path.join(a.build, "compile_commands.json")
        if not os.path.isfile(db):
            sys.stderr.write(f"function_length: {db}: missing (configure with CMAKE_EXPORT_COMPILE_COMMANDS)\n")
            return 2
        roots = [os.path.join(source, d.rstrip("/")) + os.sep for d in a.dirs]
        files, seen = [], set()
        with open(db, encoding="utf-8") as f:
            for e in json.load(f):
                p = os.path.realpath(os.path.join(e.get("directory", ""), e["file"]))
                if p in seen or not any(p.startswith(r) for r in roots):
                    continue
                seen.add(p)
                files.append((p, compile_args(e, p)))
        # Sources under the directories that the build does not compile (e.g. without Vulkan) are
        # not checked: say so rather than pass quietly.
        for r in roots:
            for dp, _, names in os.walk(r):
                for n in names:
                    p = os.path.realpath(os.path.join(dp, n))
                    if n.endswith((".cpp", ".cc")) and p not in seen:
                        sys.stderr.write(f"function_length: note: {os.path.relpath(p, source)} is not in the build, not checked\n")

    def wanted(path):
        return any(path.startswith(r) for r in roots)

    found, failed = {}, False
    with ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for path, f, errors in pool.map(lambda fa: parse(fa[0], fa[1], wanted), files):
            for d in errors[:5]:
                sys.stderr.write(f"function_length: {os.path.relpath(path, source)}: parse error: {d}\n")
            failed |= bool(errors)
            found.update(f)

    allowed = read_allowlist(a.allow, source)
    used = set()
    offenders = []
    for (path, _), (name, start, end) in sorted(found.items()):
        length = end - start + 1
        if length <= a.max:
            continue
        with open(path, encoding="utf-8", errors="replace") as fh:
            lines = fh.read().split("\n")
        rel = os.path.relpath(path, source)
        if reason_for(lines, start):
            continue
        if (path, name) in allowed:
            used.add((path, name))
            continue
        offenders.append(f"{rel}:{start}: {name}: {length} lines (limit {a.max}); add '// Long: <reason>' above it or split it")
    for (path, name), (n, _) in sorted(allowed.items()):
        if (path, name) not in used:
            offenders.append(f"{a.allow}:{n}: {name} in {os.path.relpath(path, source)} is not a function over "
                             f"{a.max} lines any more: remove it from the list")
    for o in offenders:
        print(o)
    print(f"function_length: {len(found)} functions in {len(files)} files, {len(offenders)} problems")
    if failed:
        print("function_length: parse errors (above): lengths may be missing")
        return 1
    return 1 if offenders else 0


if __name__ == "__main__":
    sys.exit(main())

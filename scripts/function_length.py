#!/usr/bin/env python3
"""Lists function definitions longer than a limit (80 lines) in the project's C++ sources.

A long function passes when a comment line starting `// Long:` gives the reason, either on the
function's first line or in the comment block directly above it (the line before the function, or a
`// Long:` line further up that block when the reason needs more than one line). Functions whose source
cannot carry the comment may be named in an allowlist (scripts/long_functions.txt): one line per
function, `path<TAB or spaces>qualified name<spaces>-- reason`. An allowlisted function that is no
longer long, or no longer exists, is an error too, so the list stays small and true.

Functions are found with Universal Ctags (Debian: universal-ctags), which gives each definition's
first and last line without compiling, so the whole tree takes a fraction of a second and needs no
build. Every C++ source and header (.cpp .cc .cxx .h .hh .hpp .inl) under the directories is read
once; C files are not. A function's length runs from its first line (the template line, for templates,
and a return type or attributes on the lines above its name) to its closing brace. Lambdas and local
classes count as part of the function that holds them; a lambda outside any function is not a
function. Definitions without a body (`= default`, `= delete`, declarations) are not counted, and
neither are functions that only a macro expansion defines, which ctags cannot see.

Usage: function_length.py [--source SRC] [--max 80] [--allow FILE] [DIR ...]
         (DIRs relative to SRC; default app core emu gpu/src verify refs)
       function_length.py --files FILE ... (just these files; for the self-test fixture and quick checks)
--build and --jobs are accepted and ignored: nothing needs a build, and one ctags process reads every file.
Exit: 0 when every long function has a reason, 1 otherwise, 2 on a usage or environment error
(e.g. Universal Ctags missing).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

SOURCE_SUFFIXES = (".cpp", ".cc", ".cxx", ".h", ".hh", ".hpp", ".inl")
DEFAULT_DIRS = ["app", "core", "emu", "gpu/src", "sim/src", "verify", "refs"]


def find_ctags():
    """The Universal Ctags executable; other ctags (Exuberant, Emacs) give no end lines."""
    for name in ("ctags", "universal-ctags", "ctags-universal"):
        exe = shutil.which(name)
        if not exe:
            continue
        try:
            out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
        except (OSError, subprocess.SubprocessError):
            continue
        if "Universal Ctags" in out:
            return exe
    sys.stderr.write("function_length: Universal Ctags is missing (Debian: apt-get install universal-ctags; "
                     "scripts/bootstrap.sh installs it)\n")
    sys.exit(2)


def run_ctags(exe, files):
    """Tags of functions and of the scopes that may hold them, one dict per tag."""
    # --options=NONE: a user's ~/.ctags.d must not change kinds, fields or extras; --quiet before it
    # silences the notice that it prints. --excmd=number leaves no search pattern (which may hold tabs)
    # in the output, so each line splits cleanly on tabs.
    cmd = [exe, "--quiet", "--options=NONE", "-f", "-", "--language-force=C++", "--kinds-C++=fncsu",
           "--fields=+neKZ", "--excmd=number", "--sort=no", "-L", "-"]
    proc = subprocess.run(cmd, input="\n".join(files) + "\n", capture_output=True, encoding="utf-8",
                          errors="replace")
    if proc.returncode != 0:
        sys.stderr.write(f"function_length: ctags failed (exit {proc.returncode}):\n{proc.stderr}")
        sys.exit(2)
    sys.stderr.write(proc.stderr)
    tags = []
    for line in proc.stdout.splitlines():
        cols = line.split("\t")
        if len(cols) < 4 or line.startswith("!_"):
            continue
        # Extension fields go in by their own keys: a `file:` field (file scope) must not clobber the path.
        tag = dict(field.partition(":")[::2] for field in cols[4:])
        tag.update(name=cols[0], path=cols[1], kind=cols[3])
        tags.append(tag)
    return tags


def is_lambda(tag):
    return tag["kind"] == "function" and tag["name"].startswith("__anon")


def qualified_name(tag, kinds):
    """ns::Class::name, with `(anonymous)` for unnamed namespaces and unnamed classes left out."""
    parts = []
    scope = tag.get("scope", "").partition(":")[2]
    prefix = ""
    for p in scope.split("::") if scope else []:
        prefix = f"{prefix}::{p}" if prefix else p
        if p.startswith("__anon"):
            if kinds.get((tag["path"], prefix)) == "namespace":
                parts.append("(anonymous)")
            continue
        parts.append(p)
    # ctags writes `operator ==`; the allowlist spells operators as C++ does (`operator==`, `operator bool`).
    name = re.sub(r"^operator\s+(?=[^\w\s])", "operator", tag["name"])
    parts.append(name)
    return "::".join(parts)


def first_line(lines, line):
    """The line where a definition starts: ctags points at its name, and the template line, a return
    type or attributes may sit on the lines above it. Those lines end in none of ; { } : and are not
    blank, comments or preprocessor lines; a line that does belongs to whatever comes before."""
    i = line - 1  # 0-based index of the line ctags gave
    while i > 0:
        prev = lines[i - 1]
        s = prev.strip()
        if i > 1 and lines[i - 2].rstrip().endswith("\\"):
            break  # the last line of a multi-line macro definition
        if "//" in s:
            s = s[:s.index("//")].rstrip()
        if not s or s.startswith(("#", "/*", "*")) or s.endswith(("*/", ";", "{", "}")):
            break
        if s.endswith(":") and not s.endswith("::"):
            break  # an access specifier
        i -= 1
        if s.startswith("template"):
            break  # a member template of a class template starts at its own (last) template line
    return i + 1


MACRO_NAME = re.compile(r"[A-Z][A-Z0-9_]*\Z")
DECLARED_NAME = re.compile(r"[^{};()]*?(~?[A-Za-z_]\w*(?:\s*::\s*~?[A-Za-z_]\w*)*)\s*\(")


def after_macro(lines, line, end, name):
    """A macro invocation that needs no semicolon (`RS_FIELDS(a, b)` in a struct) and the function
    after it read as one declaration: ctags names the function after the macro and starts it at the
    macro. Returns the function's own (name, first line), or None when the tag is no such pair (a
    function whose name a macro writes, `void RS_ISA(Spheres)(...)`, keeps its tag)."""
    if not MACRO_NAME.match(name):
        return None
    text = "\n".join(lines[line - 1:end])
    m = re.search(r"\b" + name + r"\s*\(", text)
    if not m:
        return None
    depth, i = 0, m.end() - 1
    for i in range(m.end() - 1, len(text)):
        depth += {"(": 1, ")": -1}.get(text[i], 0)
        if depth == 0:
            break
    rest = text[i + 1:]
    d = DECLARED_NAME.match(rest)
    if not d:
        return None
    first = i + 1 + len(rest) - len(rest.lstrip())
    return re.sub(r"\s+", "", d.group(1)), line + text.count("\n", 0, first)


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


def list_sources(source, dirs):
    files = []
    for d in dirs:
        root = os.path.join(source, d)
        if not os.path.isdir(root):
            sys.stderr.write(f"function_length: {root}: not a directory\n")
            sys.exit(2)
        for dp, dns, names in os.walk(root):
            dns.sort()
            files += [os.path.join(dp, n) for n in sorted(names) if n.endswith(SOURCE_SUFFIXES)]
    return files


def find_functions(files):
    """{(real path, first line): (qualified name, first line, last line)} of every definition with a
    body, outermost only; and the problems met."""
    exe = find_ctags()
    tags = run_ctags(exe, files)
    kinds = {}
    for t in tags:
        scope = t.get("scope", "").partition(":")[2]
        kinds[(t["path"], f"{scope}::{t['name']}" if scope else t["name"])] = t["kind"]
    by_file, problems = {}, []
    for t in tags:
        if t["kind"] != "function":
            continue
        if "end" not in t:
            problems.append(f"{t['path']}:{t['line']}: {t['name']}: ctags found no end line")
            continue
        by_file.setdefault(t["path"], []).append(t)
    found = {}
    for file, ts in by_file.items():
        # A tag inside another function's lines (lambda, local class method) is part of that function.
        ranges = [(int(t["line"]), int(t["end"])) for t in ts]
        with open(file, encoding="utf-8", errors="replace") as fh:
            lines = fh.read().split("\n")
        path = os.path.realpath(file)
        for t, (line, end) in zip(ts, ranges):
            if is_lambda(t) or any(s <= line and end <= e and (s, e) != (line, end) for s, e in ranges):
                continue
            own = after_macro(lines, line, end, t["name"])
            if own:
                t = dict(t, name=own[0])
                start = own[1]
            else:
                start = first_line(lines, line)
            found[(path, start)] = (qualified_name(t, kinds), start, end)
    return found, problems


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", help="ignored (no build or compile database is needed)")
    ap.add_argument("--source", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--max", type=int, default=80, help="longest function allowed without a reason (lines)")
    ap.add_argument("--allow", help="allowlist file (path name -- reason per line)")
    ap.add_argument("--files", nargs="+", help="check these files alone")
    ap.add_argument("--jobs", type=int, help="ignored (one ctags process reads every file)")
    # Every function with its first and last line, to check what ctags made of a construct by hand.
    ap.add_argument("--dump", metavar="FILE", help=argparse.SUPPRESS)
    ap.add_argument("dirs", nargs="*", default=DEFAULT_DIRS)
    a = ap.parse_args()
    source = os.path.realpath(a.source)

    if a.files:
        for f in a.files:
            if not os.path.isfile(f):
                sys.stderr.write(f"function_length: {f}: no such file\n")
                return 2
        files = [os.path.abspath(f) for f in a.files]
    else:
        files = list_sources(source, a.dirs)

    found, problems = find_functions(files)
    if a.dump:
        with open(a.dump, "w", encoding="utf-8") as df:
            for (path, _), (name, start, end) in sorted(found.items()):
                df.write(f"{os.path.relpath(path, source)}\t{start}\t{end}\t{end - start + 1}\t{name}\n")

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
    if problems:
        for p in problems:
            print(f"function_length: {p}")
        print("function_length: ctags could not delimit the functions above: lengths may be missing")
        return 1
    return 1 if offenders else 0


if __name__ == "__main__":
    sys.exit(main())

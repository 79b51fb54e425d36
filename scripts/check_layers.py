#!/usr/bin/env python3
"""The libraries' order (docs/architecture.md, "Libraries"): each library's sources may include the
headers of the libraries its row names under "may include", and of no other; each row's "lines"
(every .h, .cpp, .glsl and .comp file of its folders, tests excluded, as wc -l counts them) must be
within 10 % of the tree's.

    python3 scripts/check_layers.py [--root DIR]     exit 1 listing every violation, 0 when none
    python3 scripts/check_layers.py --lines          print each library's lines now
    python3 scripts/check_layers.py --write-lines    set the table's "lines" column to them
"""
import argparse
import pathlib
import re
import sys

SOURCE = re.compile(r'\.(h|cpp|glsl|comp)$')
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def parse_table(doc):
    """Rows of the Libraries table: (names, folders, may_include) each a list."""
    text = doc.read_text()
    start = text.index('## Libraries')
    end = text.index('\n## ', start + 1)
    rows = []
    for line in text[start:end].splitlines():
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if len(cells) < 5 or not cells[0].startswith('`'):
            continue
        names = re.findall(r'`(rayspace_\w+)`', cells[0])
        folders = [f.rstrip('/') for f in re.findall(r'`([^`]+/)`', cells[1])]
        may = re.findall(r'`(rayspace_\w+)`', cells[3])
        lines = int(cells[4].replace(',', '')) if cells[4].replace(',', '').isdigit() else None
        rows.append((names, folders, may, lines))
    return rows


def files_of(root, folder, others):
    """Every source file under folder that no deeper listed folder claims; tests excluded."""
    base = root / folder
    for p in sorted(base.rglob('*')):
        rel = p.relative_to(root).as_posix()
        if not p.is_file() or not SOURCE.search(p.name) or '/tests/' in '/' + rel:
            continue
        if any(o != folder and (rel + '/').startswith(o + '/') and len(o) > len(folder) for o in others):
            continue
        yield p


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--root', default=str(pathlib.Path(__file__).resolve().parent.parent))
    ap.add_argument('--lines', action='store_true')
    ap.add_argument('--write-lines', action='store_true')
    args = ap.parse_args()
    root = pathlib.Path(args.root)
    rows = parse_table(root / 'docs' / 'architecture.md')
    if not rows:
        print('check_layers: no Libraries table in docs/architecture.md', file=sys.stderr)
        return 2
    all_folders = [f for r in rows for f in r[1]]
    owner = {}    # header path relative to an include root -> the row's names
    local = {}    # folder -> the row's names, for includes relative to the including file
    for names, folders, _, _ in rows:
        for folder in folders:
            local[folder] = ', '.join(names)
            for p in files_of(root, folder, all_folders):
                for part in ('include',):
                    rel = p.relative_to(root / folder).as_posix()
                    if rel.startswith(part + '/'):
                        owner[rel[len(part) + 1:]] = ', '.join(names)
    problems = []
    counts = {}
    for names, folders, may, lines in rows:
        allowed = set(names) | set(may)
        total = 0
        for folder in folders:
            for p in files_of(root, folder, all_folders):
                text = p.read_text(errors='replace')
                total += text.count('\n')
                for inc in INCLUDE.findall(text):
                    lib = owner.get(inc)
                    if lib is None:
                        # A file beside it, or under another listed folder by a path relative to it.
                        target = (p.parent / inc).resolve()
                        for f in all_folders if target.is_file() else []:
                            if str(target).startswith(str((root / f).resolve()) + '/'):
                                deepest = max((g for g in all_folders if str(target).startswith(str((root / g).resolve()) + '/')), key=len)
                                lib = local[deepest]
                                break
                    if lib is None:
                        # A header found through another folder's include path (-I app/ and the like).
                        found = {local[f] for f in all_folders if (root / f / inc).is_file() and
                                 not any(g != f and (root / f / inc).resolve().is_relative_to((root / g).resolve()) and len(g) > len(f)
                                         for g in all_folders)}
                        lib = found.pop() if len(found) == 1 else None
                    if lib is not None and not set(lib.split(', ')) & allowed:
                        problems.append(f'{p.relative_to(root)}: includes "{inc}" of {lib}; {names[0]} may include only '
                                        f'{", ".join(sorted(allowed))} (docs/architecture.md)')
        counts[names[0]] = total
        if not (args.lines or args.write_lines) and lines is not None and abs(total - lines) > 0.1 * max(lines, 1):
            problems.append(f'docs/architecture.md: {names[0]} has {total} lines, the table says {lines} (more than 10 % off)')
    if args.lines:
        for name, n in counts.items():
            print(f'{name} {n}')
        return 0
    if args.write_lines:
        doc = root / 'docs' / 'architecture.md'
        out = []
        for line in doc.read_text().split('\n'):
            m = re.match(r'\| `(rayspace_\w+)`', line)
            if m and m.group(1) in counts:
                line = re.sub(r'\| [0-9,]+ \|$', f'| {counts[m.group(1)]:,} |', line)
            out.append(line)
        doc.write_text('\n'.join(out))
        return 0
    for p in problems:
        print(p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())

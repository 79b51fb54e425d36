#!/usr/bin/env python3
"""Writes scenes/manifest.json: every file under the data root that the bundled scenes need.

For each scene JSON in scenes/ the files are its objects' meshes and the material files their
OBJ `mtllib` lines name (a missing MTL is not needed: the loader falls back to a default material).
Each file gets its size, SHA-256, and the source and licence that its directory's SOURCE.txt
states. The output depends only on the data, so a rerun over the same root gives the same bytes.

Usage: scripts/make_manifest.py --data DIR [--scenes DIR] [--out FILE | --check FILE]
"""
import argparse
import hashlib
import json
import os
import re
import sys
import urllib.parse


def fail(msg):
    print(f"make_manifest.py: {msg}", file=sys.stderr)
    sys.exit(2)


def mtllibs(obj_path):
    names = []
    with open(obj_path, "rb") as f:
        for line in f:
            if line.startswith(b"mtllib"):
                names += line.decode("utf-8", "replace").split()[1:]
    return names


def needed_files(scene_path, data):
    with open(scene_path, encoding="utf-8") as f:
        scene = json.load(f)
    files = []
    for obj in scene.get("objects", []):
        mesh = obj.get("mesh")
        if not mesh or os.path.exists(os.path.join(os.path.dirname(scene_path), mesh)):
            continue  # procedural, or a file beside the scene (not data-root data)
        if not os.path.isfile(os.path.join(data, mesh)):
            fail(f"{scene_path}: mesh {mesh} is not under the data root {data}")
        files.append(mesh)
        if mesh.endswith(".obj"):
            d = os.path.dirname(mesh)
            files += [p for p in (os.path.join(d, n) for n in mtllibs(os.path.join(data, mesh)))
                      if os.path.isfile(os.path.join(data, p))]
    return sorted(set(files))


def field(text, name):
    m = re.search(rf"^\s*{name}\s*:\s*(.+)$", text, re.M)
    return m.group(1).strip() if m else ""


def section(text, heading):
    """The lines after a heading line up to the next unindented heading, whitespace collapsed."""
    m = re.search(rf"^{re.escape(heading)}[^\n]*\n((?:[ \t]+[^\n]*\n|\n)*)", text, re.M)
    return " ".join(m.group(1).split()) if m else ""


def source_of(data, directory):
    path = os.path.join(data, directory, "SOURCE.txt")
    if not os.path.isfile(path):
        fail(f"{path}: missing (every data directory states its source and licence)")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    repo, commit = field(text, "GitHub repo").split(" ")[0], field(text, "commit")
    # The path value may be quoted and may carry a parenthesised note after two spaces.
    src_path = re.split(r"\s{2,}|\s\(", field(text, "path"))[0].strip().strip('"')
    licence = section(text, "Licence")
    one_line = False
    if not repo:
        # The one-line form of a Sources entry: "FILE: GitHub repo OWNER/NAME, commit SHA, path P." The
        # first entry is the directory's source; a data file it does not name is refused (file_url), so
        # a file of another entry never gets this one's url. Its licence: the entry's parenthesis that
        # speaks of one ("source: Blender; no licence given").
        m = re.search(r"GitHub repo (\S+), commit ([0-9a-f]{40}),\s+paths? ([^\s,]+?)[.,]?(?:\s|$)", text)
        if m:
            repo, commit, src_path, one_line = m.group(1), m.group(2), m.group(3), True
            entry = text[m.start():text.find("\n\n", m.start()) if "\n\n" in text[m.start():] else len(text)]
            lic = re.search(r"\(([^)]*licen[cs]e[^)]*)\)", entry)
            licence = licence or (lic.group(1).strip() if lic else "")
    # A path line may list several files of one directory: "dir/a.ply, b.ply, c.ply"; each file of
    # the data is then matched by name (file_url), and the source's own url is the first's.
    names = [n.strip() for n in src_path.split(",") if n.strip()]
    src_dir = os.path.dirname(names[0]) if names else ""
    src_files = [names[0]] + [n if "/" in n else f"{src_dir}/{n}" for n in names[1:]] if names else []
    src_path = src_files[0] if src_files else src_path
    if not repo or not commit:
        fail(f"{path}: no 'GitHub repo' or 'commit' line")
    url = f"https://github.com/{repo}/blob/{commit}/{urllib.parse.quote(src_path)}"
    return {
        "description": text.splitlines()[0].removeprefix("SCENE:").strip(),
        "repository": f"https://github.com/{repo}",
        "commit": commit,
        "path": src_path,
        "url": url,
        "licence": licence,
        "one_line": one_line,
        "source_file": f"{directory}/SOURCE.txt",
        "files": src_files,
    }


def file_url(src, rel):
    """The url of the source file a data file is a copy of (same name), else the source's first."""
    for f in src.get("files", []):
        if os.path.basename(f) == os.path.basename(rel):
            return f"{src['repository']}/blob/{src['commit']}/{urllib.parse.quote(f)}"
    if src.get("one_line"):
        fail(f"{rel}: its directory's SOURCE.txt entry names {src['path']}, not this file")
    return src["url"]


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def manifest(data, scenes_dir):
    scenes, files = {}, {}
    for name in sorted(os.listdir(scenes_dir)):
        if not name.endswith(".json") or name == "manifest.json":
            continue
        needed = needed_files(os.path.join(scenes_dir, name), data)
        scenes[name] = needed
        for rel in needed:
            files.setdefault(rel, []).append(name)
    sources = {d: source_of(data, d) for d in sorted({rel.split("/")[0] for rel in files})}
    entries = []
    for rel in sorted(files):
        full = os.path.join(data, rel)
        src = sources[rel.split("/")[0]]
        # A file named as the source's is a byte-for-byte copy; another was converted from it (SOURCE.txt says how).
        copy = any(os.path.basename(rel) == os.path.basename(f) for f in src["files"])
        entries.append({"path": rel, "size": os.path.getsize(full), "sha256": sha256(full),
                        "source": rel.split("/")[0], "url": file_url(src, rel), "obtained": "copy" if copy else "converted",
                        "scenes": files[rel]})
    for src in sources.values():
        del src["files"], src["one_line"]  # only for the entries' urls
    return {"format": 1,
            "about": "Files under the data root the bundled scenes need; regenerate with scripts/make_manifest.py",
            "scenes": scenes, "files": entries, "sources": sources}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", required=True, help="the data root")
    ap.add_argument("--scenes", default=os.path.join(os.path.dirname(__file__), "..", "scenes"))
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--out", help="write here (default: <scenes>/manifest.json)")
    group.add_argument("--check", help="exit 1 when this file differs from what would be written")
    a = ap.parse_args()
    if not os.path.isdir(a.data):
        fail(f"--data {a.data}: not a directory")
    text = json.dumps(manifest(a.data, a.scenes), indent=2, ensure_ascii=False) + "\n"
    if a.check:
        with open(a.check, encoding="utf-8") as f:
            if f.read() != text:
                print(f"make_manifest.py: {a.check} is out of date; run scripts/make_manifest.py --data {a.data}",
                      file=sys.stderr)
                sys.exit(1)
        return
    out = a.out or os.path.join(a.scenes, "manifest.json")
    tmp = out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, out)


if __name__ == "__main__":
    main()

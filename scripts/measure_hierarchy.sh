#!/usr/bin/env bash
# Regenerates the hierarchy table of docs/performance.md: every bundled scene with every algorithm at
# 512x512 (one run each, oracle on), printed as markdown rows. Usage: scripts/measure_hierarchy.sh [DATA]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
data=${1:-$root/../shared/scenes}
exe=$root/build/app/rayspace
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
row() {  # scene algo [extra args]
  local scene=$1 algo=$2
  shift 2
  "$exe" render "$root/scenes/$scene.json" --data "$data" --algo "$algo" --stats "$work/s.json" --out "$work/i.png" "$@" > /dev/null
  python3 - "$work/s.json" "$scene" "$algo" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
ph = {p["phase"]: p["ms"] for p in j["phases"]}
sort = ph.get("ray_compression", 0) + ph.get("ray_sorting", 0) + ph.get("ray_decompression", 0)
trav, fin = ph.get("hierarchy_traversal", 0), ph.get("final_intersection_tests", 0)
total, brute = j["total_tests"], j["brute_force_tests"]
m = j["oracle"]["mismatches"]
m = len(m) if isinstance(m, list) else int(m)
rate = "n/a" if sys.argv[3] == "brute" else "%.0f" % (total / ((trav + fin) / 1000) / 1e6)
print("| %s | %s | {:,} | %.2f%% | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %s | %d |".format(total) % (
    sys.argv[2], sys.argv[3], 100.0 * total / brute, j["frame_ms"], ph.get("ray_creation", 0), sort,
    ph.get("hierarchy_creation", 0), trav, fin, rate, m))
PY
}
echo "| scene | algorithm | total tests | % brute force | frame | ray creation | sort | build | traversal | final tests | M tests/s | mismatches |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for scene in cornell-mirrors office sponza; do
  for algo in crsh rah rah-quadtree brute; do row "$scene" "$algo"; done
done
echo
"$exe" render "$root/scenes/sponza.json" --data "$data" --depth 3 --no-oracle --stats "$work/s.json" --out "$work/i.png" > /dev/null
python3 -c "import json; j = json.load(open('$work/s.json')); print('sponza --depth 3: {:,} tests ({:.2f}%)'.format(j['total_tests'], 100.0 * j['total_tests'] / j['brute_force_tests']))"

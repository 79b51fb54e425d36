#!/usr/bin/env bash
# Where --objects tree overtakes flat: about 60,000 glass triangles in front of a mirror wall, as
# 1, 4, 16 or 64 copies of the Stanford bunny (its four levels of detail, 69,451 / 16,301 / 3,851 /
# 948 triangles), each copy scaled to its cell of a square grid, so that every scene fills the same
# view with the same surface; then the bundled scenes. One `rayspace bench` run per scene with
# crsh-flat, crsh-tree and crsh (render's default, --objects auto), medians of 3 frames.
# Usage: scripts/measure_objects.sh [DATA] [SIZE]   (DATA: the scene data root; SIZE default 256x256)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
data=${1:-$root/../shared/scenes}
size=${2:-256x256}
exe=$root/build/app/rayspace
work=$(mktemp -d)
[[ -n "${KEEP_SCENES:-}" ]] || trap 'rm -rf "$work"' EXIT

# scene NAME MESH K: K x K copies of MESH on a 4 x 4 square at the origin (the bunny is 0.155 wide).
scene() {
  local name=$1 mesh=$2 k=$3 instances="" i j
  local cell scale
  cell=$(awk -v k="$k" 'BEGIN { printf "%.6f", 4.0 / k }')
  scale=$(awk -v c="$cell" 'BEGIN { printf "%.6f", 0.85 * c / 0.155 }')
  for ((i = 0; i < k; i++)); do
    for ((j = 0; j < k; j++)); do
      local x y
      x=$(awk -v c="$cell" -v i="$i" 'BEGIN { printf "%.6f", -2 + c * (i + 0.5) + 0.02 * c }')
      y=$(awk -v c="$cell" -v j="$j" -v s="$scale" 'BEGIN { printf "%.6f", -2 + c * j - 0.033 * s }')
      instances+="${instances:+, }{\"scale\": $scale, \"rotate_deg\": [0, $(( (i * 37 + j * 53) % 360 )), 0], \"translate\": [$x, $y, 0]}"
    done
  done
  cat > "$work/$name.json" <<JSON
{
  "name": "$name",
  "camera": {"eye": [0, 0, 6.5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40},
  "image": {"width": 256, "height": 256},
  "lights": [{"position": [3, 6, 8], "color": [1, 1, 1], "intensity": 1.2, "attenuation": [1, 0, 0.001]}],
  "materials": {
    "glass": {"diffuse": [0.04, 0.05, 0.05], "specular": [0.8, 0.8, 0.8], "shininess": 128,
              "reflectivity": 0.1, "transparency": 0.85, "ior": 1.5},
    "mirror": {"diffuse": [0.08, 0.08, 0.1], "specular": [0.5, 0.5, 0.5], "shininess": 96, "reflectivity": 0.85}
  },
  "objects": [
    {"name": "bunnies", "mesh": "$mesh", "material": "glass", "instances": [$instances]},
    {"name": "wall", "generator": "wavy", "params": {"size": 12, "amplitude": 0.05, "frequency": 1, "resolution": 16},
     "material": "mirror", "transform": {"rotate_deg": [90, 0, 0], "translate": [0, 0, -2]}}
  ],
  "max_depth": 3
}
JSON
  echo "$work/$name.json"
}

scenes=(
  "$(scene bunny-1x69k bunny/bun_zipper.ply 1)"
  "$(scene bunny-4x16k bunny/bun_zipper_res2.ply 2)"
  "$(scene bunny-16x3.9k bunny/bun_zipper_res3.ply 4)"
  "$(scene bunny-64x0.9k bunny/bun_zipper_res4.ply 8)"
)
"$exe" bench "${scenes[@]}" --data "$data" --sizes "$size" --repetitions 3 --configs crsh-flat,crsh-tree,crsh
"$exe" bench "$root"/scenes/*.json --data "$data" --sizes "$size" --repetitions 3 --configs crsh-flat,crsh-tree,crsh

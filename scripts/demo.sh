#!/usr/bin/env bash
# The main job: bootstrap, build, render the demo scene, print its statistics, write the image.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/bootstrap.sh
scripts/build.sh
mkdir -p out
./build/app/rayspace render scenes/cornell-mirrors.json --out out/cornell-mirrors.png --stats out/cornell-mirrors.json
echo "image written to out/cornell-mirrors.png, statistics to out/cornell-mirrors.json"

#!/usr/bin/env bash
# The first image: bootstrap, build the `rayspace` command alone, render the demo scene, print its
# statistics, write the image. Each step says what it does; the build prints its progress.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
step() { echo "demo: [$((SECONDS - start)) s] $*"; }
step "installing the Debian packages the rayspace command needs (scripts/bootstrap.sh --build-only)"
scripts/bootstrap.sh --build-only
step "building the rayspace command (build/app/rayspace)"
RAYSPACE_TESTS=OFF scripts/build.sh rayspace
step "rendering scenes/cornell-mirrors.json"
mkdir -p out
./build/app/rayspace render scenes/cornell-mirrors.json --out out/cornell-mirrors.png --stats out/cornell-mirrors.json
step "image written to out/cornell-mirrors.png, statistics to out/cornell-mirrors.json"

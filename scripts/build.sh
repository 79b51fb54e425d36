#!/usr/bin/env bash
# Configures and builds rayspace in ./build (Release). Used by demo.sh and test.sh.
#   scripts/build.sh [TARGET...]   the given targets only (demo.sh builds `rayspace`); all without one
set -euo pipefail
cd "$(dirname "$0")/.."
# Compiler-cache entries keyed on paths relative to the clone, so every clone of the tree shares them.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
# The bootstrap installs the Vulkan backend's dependencies: a missing one must fail the build here.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAYSPACE_VULKAN=ON >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j"$(nproc)" "${targets[@]}"

#!/usr/bin/env bash
# Configures and builds rayspace in ./build (Release). Used by demo.sh and test.sh.
#   scripts/build.sh [TARGET...]   the given targets only (demo.sh builds `rayspace`); all without one
set -euo pipefail
cd "$(dirname "$0")/.."
# Compiler-cache entries keyed on paths relative to the clone, so every clone of the tree shares them.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$PWD}"
# The bootstrap installs the Vulkan backend's dependencies: a missing one must fail the build here.
# Ninja when it is there: it starts a target's compiles before the libraries it links are linked,
# which Make does not (a cold build of `rayspace` took about 210 s with Ninja on 2 cores). A
# build folder made by another generator keeps it.
generator=()
if command -v ninja >/dev/null && { [ ! -f build/CMakeCache.txt ] || grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; }; then
  generator=(-G Ninja)
fi
# RAYSPACE_TESTS=OFF (scripts/demo.sh) configures without the tests, so doctest is not needed.
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DRAYSPACE_VULKAN=ON \
  -DRAYSPACE_TESTS="${RAYSPACE_TESTS:-ON}" >/dev/null
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j"$(nproc)" "${targets[@]}"

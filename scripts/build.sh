#!/usr/bin/env bash
# Configures and builds rayspace in ./build (Release). Used by demo.sh and test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
# The bootstrap installs the Vulkan backend's dependencies: a missing one must fail the build here.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAYSPACE_VULKAN=ON >/dev/null
cmake --build build -j"$(nproc)"

#!/usr/bin/env bash
# The test job: bootstrap, build, run every test with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/bootstrap.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)"

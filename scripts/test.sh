#!/usr/bin/env bash
# The test job: bootstrap, build, run one tier of the tests with ctest (docs/verification.md, "Test tiers").
#   scripts/test.sh [--full] [-- CTEST_ARGS...]
#   (no option)  the default tier (ctest label `default`): unit tests, every pass's diff on small frames,
#                planted faults, the CLI contract; under 10 minutes of ctest on 2 cores
#   --full       every test: the default tier and the full tier (label `full`: the mutation sample,
#                Sponza diffs, reproduce, data tests); what CI runs
# Arguments after `--` go to ctest (e.g. `-- -R cli.diff`).
set -euo pipefail
cd "$(dirname "$0")/.."
tier=(-L '^default$')
while [ $# -gt 0 ]; do
  case "$1" in
    --full) tier=(); shift ;;
    --) shift; break ;;
    -h|--help) sed -n '2,8s/^# \{0,1\}//p' "$0"; exit 0 ;;
    *) echo "scripts/test.sh: unknown argument '$1' (usage: scripts/test.sh [--full] [-- CTEST_ARGS...])" >&2; exit 2 ;;
  esac
done
scripts/bootstrap.sh
scripts/build.sh
ctest --test-dir build --output-on-failure -j"$(nproc)" "${tier[@]}" "$@"

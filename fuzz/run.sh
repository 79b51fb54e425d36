#!/usr/bin/env bash
# Builds the libFuzzer harnesses with clang (build-fuzz/, RAYSPACE_FUZZ=ON) and runs each for N
# seconds from a fresh random seed, starting from the committed seed corpus; prints exec/s and any
# finding. Usage: fuzz/run.sh [SECONDS=60] [HARNESS...]
set -euo pipefail
secs=${1:-60}
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(cone_union cone_grow cone_sphere ray_triangle scene_load)
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RAYSPACE_FUZZ_BUILD:-$root/build-fuzz}

CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DRAYSPACE_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build "$build" -j "$(nproc)" --target "${harnesses[@]}" > "$build/build.log" 2>&1 || { tail -30 "$build/build.log"; exit 1; }

failed=0
printf '%-13s %11s %12s %10s  %s\n' harness seed executions exec/s result
for h in "${harnesses[@]}"; do
  work="$build/run/$h"
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  seed=$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')
  log="$work/log.txt"
  rc=0
  "$build/fuzz/$h" -seed="$seed" -max_total_time="$secs" -print_final_stats=1 -timeout=10 -rss_limit_mb=4096 \
    -artifact_prefix="$work/artifacts/" "$work/corpus" "$root/fuzz/corpus/$h" > "$log" 2>&1 || rc=$?
  execs=$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  execs=${execs:-0}
  if [ $rc -eq 0 ]; then
    result="no finding"
  else
    result="FINDING (exit $rc): $(grep -m1 -E 'FINDING|ERROR: AddressSanitizer|runtime error|deadly signal' "$log" || true); reproducer in $work/artifacts/"
    failed=1
  fi
  printf '%-13s %11s %12s %10s  %s\n' "$h" "$seed" "$execs" "$((execs / secs))" "$result"
done
exit $failed

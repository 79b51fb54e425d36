#!/usr/bin/env bash
# Builds the libFuzzer harnesses with clang (build-fuzz/, RAYSPACE_FUZZ=ON) and runs each for the
# given seconds, from a fresh random seed or the one given, starting from the committed seed corpus
# and the corpus earlier runs grew; prints exec/s, any finding, and where everything is.
#
# Usage: fuzz/run.sh --harness NAME[,NAME...]|all --seconds N [--seed S]
#   --harness  which harnesses to run (the names in fuzz/CMakeLists.txt), or all of them
#   --seconds  how long each one runs: a whole number of seconds, 1 to 604800 (a week)
#   --seed     libFuzzer's seed, 1 to 4294967295, to rerun a run the table printed (default: random)
# --harness and --seconds are required, so that neither can be taken for the other.
# Each harness keeps, under build-fuzz/run/NAME/: corpus/ (grown by every run, never deleted) and one
# directory per run, named by its time and seed, with its log and its reproducers (artifacts/).
# Exit: 0 no finding, 1 a finding or the build failed, 2 bad arguments (one line on stderr naming
# the argument; nothing is built).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
usage="usage: fuzz/run.sh --harness NAME[,NAME...]|all --seconds N [--seed S]"

# The harness names, from the one list the build uses.
known=$(sed -n 's/^set(RAYSPACE_HARNESSES \(.*\))$/\1/p' "$root/fuzz/CMakeLists.txt")
if [ -z "$known" ]; then
  echo "fuzz/run.sh: no RAYSPACE_HARNESSES list in fuzz/CMakeLists.txt" >&2
  exit 1
fi

bad() {
  echo "fuzz/run.sh: $1 ($usage)" >&2
  exit 2
}

harness_arg="" secs="" seed_arg=""
while [ $# -gt 0 ]; do
  case "$1" in
    -h|--help) echo "$usage"; echo "harnesses: ${known// /, }"; exit 0 ;;
    --harness|--seconds|--seed)
      [ $# -ge 2 ] || bad "$1 needs a value"
      case "$1" in --harness) harness_arg=$2 ;; --seconds) secs=$2 ;; --seed) seed_arg=$2 ;; esac
      shift 2 ;;
    --harness=*) harness_arg=${1#--harness=}; shift ;;
    --seconds=*) secs=${1#--seconds=}; shift ;;
    --seed=*) seed_arg=${1#--seed=}; shift ;;
    *) bad "unexpected argument '$1'" ;;
  esac
done
[ -n "$harness_arg" ] || bad "--harness is required"
[ -n "$secs" ] || bad "--seconds is required"
if ! [[ "$secs" =~ ^[1-9][0-9]{0,5}$ ]] || [ "$secs" -gt 604800 ]; then
  bad "--seconds '$secs': expected a whole number of seconds from 1 to 604800"
fi
if [ -n "$seed_arg" ] && { ! [[ "$seed_arg" =~ ^[1-9][0-9]{0,9}$ ]] || [ "$seed_arg" -gt 4294967295 ]; }; then
  bad "--seed '$seed_arg': expected a whole number from 1 to 4294967295"
fi
harnesses=()
if [ "$harness_arg" = all ]; then
  read -r -a harnesses <<< "$known"
else
  IFS=, read -r -a harnesses <<< "$harness_arg"
  for h in "${harnesses[@]}"; do
    [[ " $known " == *" $h "* ]] || bad "--harness '$h': unknown harness (known: ${known// /, }, or all)"
  done
fi

build=${RAYSPACE_FUZZ_BUILD:-$root/build-fuzz}
# The sanitizer build compiles the exact oracles (CGAL) from scratch: minutes on a cold compiler cache,
# so its progress lines are shown as they come (the whole log stays in build.log).
echo "fuzz/run.sh: building ${harnesses[*]} with clang in $build (log: $build/build.log)"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DRAYSPACE_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
if ! cmake --build "$build" -j "$(nproc)" --target "${harnesses[@]}" 2>&1 | tee "$build/build.log" |
    { grep --line-buffered -E '^\[ *[0-9]+%\] (Building|Linking)' || true; } | sed -u 's/^/  /'; then
  tail -30 "$build/build.log"
  exit 1
fi

failed=0
printf '%-13s %11s %12s %10s  %s\n' harness seed executions exec/s result
for h in "${harnesses[@]}"; do
  work="$build/run/$h"
  seed=${seed_arg:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}
  [ "$seed" -gt 0 ] || seed=1
  run="$work/$(date +%Y%m%d-%H%M%S)-seed$seed"
  mkdir -p "$work/corpus" "$run/artifacts"
  log="$run/log.txt"
  rc=0
  "$build/fuzz/$h" -seed="$seed" -max_total_time="$secs" -print_final_stats=1 -timeout=10 -rss_limit_mb=4096 \
    -artifact_prefix="$run/artifacts/" "$work/corpus" "$root/fuzz/corpus/$h" > "$log" 2>&1 || rc=$?
  execs=$(grep -m1 'stat::number_of_executed_units' "$log" | awk '{print $2}')
  execs=${execs:-0}
  if [ $rc -eq 0 ]; then
    result="no finding"
  else
    result="FINDING (exit $rc): $(grep -m1 -E 'FINDING|ERROR: AddressSanitizer|runtime error|deadly signal' "$log" || true); reproducer in $run/artifacts/; rerun: fuzz/run.sh --harness $h --seconds $secs --seed $seed"
    failed=1
  fi
  printf '%-13s %11s %12s %10s  %s\n' "$h" "$seed" "$execs" "$((execs / secs))" "$result"
done
echo "fuzz/run.sh: corpora (kept across runs) and each run's log and reproducers under $build/run/<harness>/"
exit $failed

#!/bin/bash
# The simulated GPU's acceptance product (docs/simulator.md, "Acceptance"): `diff --backends emu,sim`
# at SIZE on every bundled scene whose data is present, for every --algo and --objects, one line a run:
#   scene|configuration|exit|verdict|seconds
# Usage: scripts/sim_acceptance.sh RAYSPACE DATA_ROOT [SIZE] [TIMEOUT_S] [SCENE...] > table.txt
# A run past TIMEOUT_S (default 900) is stopped and reported as such; nothing is retried. SCENE names
# (cornell-mirrors, ...) choose the scenes and their order; default every bundled scene by name.
# SIM_CONFIGS (';'-separated, e.g. "crsh;crsh --objects tree") chooses the configurations.
set -u
rayspace=$1
data=$2
size=${3:-32x32}
timeout=${4:-900}
shift $(( $# < 4 ? $# : 4 ))
here=$(cd "$(dirname "$0")/.." && pwd)
scenes=()
for s in "$@"; do scenes+=("$here/scenes/$s.json"); done
[ ${#scenes[@]} -eq 0 ] && scenes=("$here"/scenes/*.json)
configs=("crsh" "crsh --objects tree" "rah" "rah-quadtree" "tl" "grid" "brute" "embree")
# SIM_CONFIGS="crsh;rah" runs those configurations only, each one of the list above.
if [ -n "${SIM_CONFIGS:-}" ]; then
  IFS=';' read -r -a chosen <<< "$SIM_CONFIGS"
  for c in "${chosen[@]}"; do
    known=0
    for k in "${configs[@]}"; do [ "$c" = "$k" ] && known=1; done
    [ $known -eq 1 ] || { echo "sim_acceptance.sh: SIM_CONFIGS '$c': not one of: ${configs[*]}" >&2; exit 2; }
  done
  configs=("${chosen[@]}")
fi
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  [ "$name" = manifest ] && continue
  # A scene whose data is not under the root is skipped, as the data-dependent tests skip.
  if ! "$rayspace" data check "$scene" --data "$data" > /dev/null 2>&1; then
    echo "$name|all|skipped|data not present|0"
    continue
  fi
  for config in "${configs[@]}"; do
    read -r -a opts <<< "$config"
    start=$(date +%s.%N)
    out=$(timeout -s KILL "$timeout" "$rayspace" diff "$scene" --data "$data" --size "$size" --backends emu,sim --algo "${opts[@]}" \
          --no-impact 2>&1)
    rc=$?
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    case $rc in
      0) verdict=$(echo "$out" | grep -m1 -oE "all passes equal[a-z' ]*") ;;
      137) verdict="stopped after ${timeout} s" ;;
      *) verdict=$(echo "$out" | grep -m1 -E "first divergent pass|error|on the kernel of" | cut -c1-200) ;;
    esac
    printf '%s|%s|%s|%s|%.0f\n' "$name" "$config" "$rc" "$verdict" "$seconds"
  done
done

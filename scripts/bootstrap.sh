#!/usr/bin/env bash
# Installs the Debian packages rayspace needs to build and test. Idempotent: installs only what is
# missing. As root it runs apt-get; otherwise it prints the command to run.
#   scripts/bootstrap.sh                what building, testing, benchmarking and fuzzing need
#   scripts/bootstrap.sh --build-only   what building and running the `rayspace` command needs (demo.sh)
set -euo pipefail

# The `rayspace` command: compilers, its libraries, the kernels' compiler and lavapipe.
BUILD=(
  build-essential cmake ninja-build ccache pkg-config
  libomp-dev libembree-dev libcgal-dev libgmp-dev libmpfr-dev libglm-dev libopenimageio-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libtinyobjloader-dev libxxhash-dev zlib1g-dev libpng-dev libssl-dev
  mesa-vulkan-drivers libvulkan-dev glslc libspirv-cross-c-shared-dev spirv-tools spirv-headers
)
# The tests (doctest, the validation layer, xmllint for the JUnit reports), benchmarks, fuzzing
# (clang's runtime), the lint (ctags) and the plots (gnuplot and its font).
MORE=(
  doctest-dev libbenchmark-dev vulkan-validationlayers libxml2-utils
  clang libclang-rt-14-dev universal-ctags gnuplot-nox fonts-dejavu-core
)
case "${1:-}" in
  "") PACKAGES=("${BUILD[@]}" "${MORE[@]}") ;;
  --build-only) PACKAGES=("${BUILD[@]}") ;;
  *) echo "scripts/bootstrap.sh: unknown argument '$1' (usage: scripts/bootstrap.sh [--build-only])" >&2; exit 2 ;;
esac

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "bootstrap: all ${#PACKAGES[@]} packages present"
  exit 0
fi

cmd="apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "bootstrap: missing packages: ${missing[*]}" >&2
  echo "bootstrap: run as root:  sudo sh -c '$cmd'" >&2
  exit 1
fi
echo "bootstrap: installing ${missing[*]}"
apt-get update -qq
# force-unsafe-io: dpkg skips its fsync per unpacked file, most of the install's time for header-heavy
# packages (Boost, CGAL); a crash mid-install would need the install run again.
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
  -o Dpkg::Options::=--force-unsafe-io "${missing[@]}"

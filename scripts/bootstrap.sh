#!/usr/bin/env bash
# Installs the Debian packages rayspace needs to build and test. Idempotent: installs only what is
# missing. As root it runs apt-get; otherwise it prints the command to run.
set -euo pipefail

PACKAGES=(
  build-essential cmake ccache pkg-config
  libomp-dev libembree-dev libcgal-dev libgmp-dev libmpfr-dev libglm-dev
  libopenimageio-dev openimageio-tools
  doctest-dev libcli11-dev nlohmann-json3-dev libfmt-dev libtinyobjloader-dev libxxhash-dev zlib1g-dev
  libbenchmark-dev
  mesa-vulkan-drivers libvulkan-dev glslc libspirv-cross-c-shared-dev spirv-tools vulkan-validationlayers
  clang libclang-rt-14-dev fonts-dejavu-core universal-ctags
  libssl-dev gnuplot-nox
)

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
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"

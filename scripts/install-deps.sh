#!/usr/bin/env bash
# Installs the Debian packages microshadow needs, only those that are missing.
# Non-interactive; safe to run repeatedly. Used by `make demo`, `make test`, `make build`; `--fuzz` (used by
# `make fuzz`) adds clang and its libFuzzer runtime.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libopenexr-dev libimath-dev libpng-dev libtbb-dev libhwy-dev
  libcli11-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev
  python3 python3-numpy python3-scipy python3-matplotlib
  glslang-tools spirv-tools mesa-vulkan-drivers libvulkan-dev
)
if [ "${1:-}" = "--fuzz" ]; then PACKAGES+=(clang-14 libclang-rt-14-dev); fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing missing Debian packages: ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Installs the Debian packages microshadow needs, only those that are missing.
# Non-interactive; safe to run repeatedly. Used by `make demo`, `make test`, `make build`; `--fuzz` (used by
# `make fuzz`) adds clang and its libFuzzer runtime.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git ccache
  libopenexr-dev libimath-dev libpng-dev libtbb-dev libhwy-dev
  libcli11-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libembree-dev
  python3 python3-numpy python3-scipy python3-matplotlib
  python3-dev python3-pybind11 pybind11-dev python3-pytest
  glslang-tools spirv-tools mesa-vulkan-drivers libvulkan-dev
  libcpp-httplib-dev libssl-dev zlib1g-dev libbrotli-dev
  chromium
)
if [ "${1:-}" = "--fuzz" ]; then PACKAGES+=(clang-14 libclang-rt-14-dev); fi
# node and npm: Debian's packages unless some node (e.g. NodeSource's, which bundles npm) is there already.
command -v node >/dev/null 2>&1 || PACKAGES+=(nodejs)
command -v npm >/dev/null 2>&1 || PACKAGES+=(npm)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The browser tests' npm packages from their committed lockfiles (node_modules is not committed): the driver
# (playwright-core) and the Khronos glTF validator (gltf-validator) in tests/browser, three.js for the three.js
# integration (integrations/three). A changed lockfile is installed again (the copy in node_modules).
install_browser_driver() {
  local root d
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  for d in "$root/tests/browser" "$root/integrations/three"; do
    if [ -f "$d/package-lock.json" ] && command -v npm >/dev/null 2>&1 &&
       ! cmp -s "$d/package-lock.json" "$d/node_modules/.msh-installed-lock.json" 2>/dev/null; then
      echo "install-deps: npm ci in ${d#"$root"/}" >&2
      (cd "$d" && npm ci --no-audit --no-fund --loglevel=error && cp package-lock.json node_modules/.msh-installed-lock.json) ||
        echo "install-deps: npm ci failed in ${d#"$root"/}: the browser tests will fail (MSH_ALLOW_NO_BROWSER=1 skips them)" >&2
    fi
  done
}

if [ ${#missing[@]} -eq 0 ]; then
  install_browser_driver
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
install_browser_driver

#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, skipping what `dpkg -s` already finds.
# Sourced by scripts/run.sh and scripts/test.sh:  hsdf_install_deps build|test
set -euo pipefail

HSDF_BUILD_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers glslang-tools glslang-dev
  libglfw3-dev libglm-dev libtinygltf-dev libimgui-dev libstb-dev
  libcli11-dev nlohmann-json3-dev libfmt-dev libdraco-dev libmeshoptimizer-dev
  libgtest-dev libbenchmark-dev
)
# openbox: X11 minimises (iconifies) a window through a window manager; the window-faults test
# runs one in Xvfb. x11-utils: xprop, to see that it has started.
HSDF_TEST_PACKAGES=(xvfb xauth openbox x11-utils)

hsdf_install_deps() {
  local wanted=("${HSDF_BUILD_PACKAGES[@]}")
  [ "${1:-build}" = test ] && wanted+=("${HSDF_TEST_PACKAGES[@]}")
  local missing=()
  for p in "${wanted[@]}"; do
    dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "Installing Debian packages: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# Vulkan's loader warns when XDG_RUNTIME_DIR is unset; give it a private folder, one per user that
# every call reuses (a new mktemp folder per call was never removed: one more per test script), or a
# fresh one where that name is taken by another user.
hsdf_runtime_env() {
  if [ -z "${XDG_RUNTIME_DIR:-}" ] || [ ! -d "${XDG_RUNTIME_DIR}" ]; then
    export XDG_RUNTIME_DIR
    XDG_RUNTIME_DIR="${TMPDIR:-/tmp}/hsdf-xdg-$(id -u)"
    if ! { mkdir -p "$XDG_RUNTIME_DIR" 2>/dev/null && [ -O "$XDG_RUNTIME_DIR" ]; }; then
      XDG_RUNTIME_DIR=$(mktemp -d /tmp/hsdf-xdg.XXXXXX)
    fi
    chmod 700 "$XDG_RUNTIME_DIR"
  fi
}

# Optional, not installed by these scripts: libopenvdb-dev and libboost-iostreams-dev for the
# OpenVDB comparison in the CPU benchmarks (-DHSDF_WITH_OPENVDB=ON, see docs/perf/cpu.md).

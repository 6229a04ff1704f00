#!/usr/bin/env bash
# Installs what is missing, builds everything (release) and runs the whole test suite with ctest.
# GPU tests run on Mesa's lavapipe with the Vulkan validation layers on; any validation message fails.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
source scripts/deps.sh
hsdf_install_deps test
hsdf_runtime_env

jobs=$(nproc)
cmake --preset release -DHSDF_WARNINGS_AS_ERRORS=ON >/dev/null
cmake --build --preset release -j "$jobs"
ctest --test-dir build/release --output-on-failure -j "$jobs" "$@"

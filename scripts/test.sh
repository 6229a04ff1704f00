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
# Every GPU test (the 1,000-frame soak among them) runs with synchronization validation as well:
# HSDF_SYNC_VALIDATION=1 makes the engine ask VK_LAYER_KHRONOS_validation for it
# (VkValidationFeaturesEXT; the layer's start-up message lists it under "Current Enables"), and
# every GPU test fails on any validation message. It costs the GPU tests about 6 % here, less than
# the separate pass over them it replaced. HSDF_SYNC_VALIDATION=0 turns it off. GPU-assisted
# validation is not run: with Debian 12's layer (1.3.239) on lavapipe it judges in-bounds
# buffer-device-address reads out of bounds and zeroes them, so every frame comes out empty
# (docs/reliability.md, "Validation stage").
HSDF_SYNC_VALIDATION=${HSDF_SYNC_VALIDATION:-1} ctest --test-dir build/release --output-on-failure -j "$jobs" "$@"

# The CPU tests again under AddressSanitizer + UndefinedBehaviorSanitizer (any report fails the
# test). HSDF_SKIP_SANITIZERS=1 skips this stage (it roughly doubles the build time).
if [ "${HSDF_SKIP_SANITIZERS:-0}" != 1 ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan -j "$jobs"
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE gpu "$@"
  # The engine's GPU tests (meshes, glTF scenes, view regions, frames in flight) on lavapipe under
  # the same sanitizers: the asan preset builds engine_gpu_tests beside the CPU tests
  # (HSDF_BUILD_ENGINE_GPU_TESTS), so the engine libraries it links are compiled once. Leak
  # checking is off: the Vulkan loader unloads lavapipe and the validation layer before
  # LeakSanitizer runs, so their allocations cannot be named by a suppression (docs/reliability.md,
  # "Sanitizers over the GPU tests"). The other GPU tests would not fit the CI's time under ASan.
  ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --test-dir build/asan --output-on-failure -j "$jobs" -R '^(GpuTest|SyncValidatedGpuTest|ViewRegionTest)\.' "$@"
fi

# Each libFuzzer target briefly (30 s each, scripts/fuzz.sh), when clang is present: the corpus
# replays above run every build; this stage lets the fuzzers look a little further on every run.
# HSDF_SKIP_FUZZ=1 skips it; HSDF_FUZZ_SECONDS changes the time per target.
if [ "${HSDF_SKIP_FUZZ:-0}" != 1 ]; then
  scripts/fuzz.sh "${HSDF_FUZZ_SECONDS:-30}"
fi

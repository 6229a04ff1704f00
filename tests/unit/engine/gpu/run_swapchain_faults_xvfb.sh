#!/usr/bin/env bash
# engine_gpu_swapchain_tests (swapchain_faults_test.cpp) in an Xvfb display, where its window and
# swapchain can be made: every test must run (a skip here means the window was not made) and pass.
# Exit 77 (ctest: skipped) when xvfb-run is not installed.
set -u
tests=$1
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIPPED: xvfb-run not found (Debian package xvfb); the swapchain faults were not run"
  exit 77
fi
source "$(cd "$(dirname "$0")/../../../gpu" && pwd)/xvfb_checks.sh" || exit 1
log=$(mktemp "${TMPDIR:-/tmp}/hsdf_swapchain_faults.XXXXXX")
in_xvfb 300 "$tests" --gtest_filter='SwapchainFaults.*' >"$log" 2>&1
rc=$?
cat "$log"
grep -q "SKIPPED \]" "$log" && { rm -f "$log"; fail "a swapchain test was skipped in the Xvfb display"; }
rm -f "$log"
[ $rc -eq 0 ] || fail "the swapchain tests exited with $rc"
echo "PASS"

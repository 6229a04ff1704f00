#!/usr/bin/env bash
# Runs the scene runner in a real GLFW window on a virtual X server, with validation on.
# Exit 77 (ctest: skipped) when Xvfb is not installed.
set -u
runner=$1
out=$2
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIPPED: xvfb-run not found (Debian package xvfb); the windowed path was not tested"
  exit 77
fi
source "$(cd "$(dirname "$0")" && pwd)/xvfb_checks.sh" || exit 1
rm -f "$out"
in_xvfb 120 "$runner" --validation --size 320x240 --frames 4 --screenshot "$out" || fail "scene_runner exited with $?"
test -s "$out" || fail "no screenshot written"

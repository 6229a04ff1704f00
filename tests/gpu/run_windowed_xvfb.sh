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
rm -f "$out"
timeout 120 xvfb-run -a -s "-screen 0 640x480x24" "$runner" --validation --size 320x240 --frames 4 --screenshot "$out" || exit 1
test -s "$out" || { echo "no screenshot written"; exit 1; }

#!/usr/bin/env bash
# The perf capture on lavapipe, as committed under docs/perf/lavapipe/: the bunny,
# 1920x1080, K = 16, 32, 64, 128, 8 orbit views. Lavapipe runs every shader on the CPU: only ratios
# within one run and the device-independent work counts mean anything. Extra arguments go to
# perf_capture (e.g. --views 2 --frames 2 for a shorter run; say so wherever its numbers are used).
# Usage: scripts/perf/capture_lavapipe.sh [build dir] [perf_capture options...]
set -euo pipefail
build=${1:-build/release}
shift || true
source "$(dirname "$0")/../deps.sh" && hsdf_runtime_env  # a private XDG_RUNTIME_DIR, reused
exec "$build/samples/perf_capture/perf_capture" --device lavapipe --out docs/perf/lavapipe \
  --size 1920x1080 --resolutions 16,32,64,128 --views 8 "$@"

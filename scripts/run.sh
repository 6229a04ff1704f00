#!/usr/bin/env bash
# Quick start: install what is missing, build a release build, run the scene runner.
# With a display it opens a window; without one it renders headless and writes a screenshot.
# Extra arguments go to the scene runner (see `build/release/samples/scene_runner/scene_runner --help`).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
source scripts/deps.sh
hsdf_install_deps build
hsdf_runtime_env

cmake --preset release >/dev/null
cmake --build --preset release --target scene_runner

runner=build/release/samples/scene_runner/scene_runner
# No arguments: the paper's comparison, Hermite cells beside trilinear sphere tracing at 2K.
[ $# -gt 0 ] || set -- --split vertical
if [ -n "${DISPLAY:-}" ] || [ -n "${WAYLAND_DISPLAY:-}" ]; then
  exec "$runner" "$@"
else
  mkdir -p out
  "$runner" --headless --ui --screenshot out/scene_runner.png "$@"
  echo "No display found: rendered headless. Screenshot: $root/out/scene_runner.png"
fi

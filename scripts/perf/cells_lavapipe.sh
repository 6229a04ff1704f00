#!/usr/bin/env bash
# First lavapipe timings of the Hermite cell renderer (issue 4): the bunny at K = 32/64/128 with
# n = 2 and 3 subdivisions, front-to-back row order on and off, all in one run, one process per
# configuration. Prints a Markdown table: GPU timestamps of the last of 5 frames, the minimum over
# 3 processes per configuration (1280x720, fixed view 0, no ground plane). Lavapipe runs on the
# CPU: compare ratios within one run only.
# Usage: scripts/perf/cells_lavapipe.sh [build dir]   (after scripts/test.sh or scripts/run.sh)
set -euo pipefail
build=${1:-build/release}
runner=$build/samples/scene_runner/scene_runner
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}
echo "| K | n | order | depth prepass (ms) | shading pass (ms) | frame (ms) |"
echo "|---|---|---|---|---|---|"
for k in 32 64 128; do
  for n in 2 3; do
    for order in front-to-back storage; do
      flag=""; [ "$order" = storage ] && flag="--no-front-to-back"
      outs=""
      for run in 1 2 3; do
        outs+=$("$runner" --headless --device lavapipe --no-ground --method cells --resolution $k --subdivisions $n \
              --refine 1 --size 1280x720 --frames 5 --view 0 $flag 2>&1)$'\n'
      done
      get() { echo "$outs" | grep -E "GPU +$1:" | awk '{print $(NF-1)}' | sort -g | head -1; }
      echo "| $k | $n | $order | $(get 'depth prepass') | $(get opaque) | $(get frame) |"
    done
  done
done

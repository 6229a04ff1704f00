#!/usr/bin/env bash
# There, on a lent GPU machine, in one device call (scripts/perf/device_pack.sh made the pack):
#   bash .device/device_run.sh [perf_capture options...]
# Unpacks .device/pack.tar.xz and, each step under its own time limit so that one call fits the
# device tool's per-call limit (HSDF_DEVICE_SECONDS, default 480, for the whole script):
#   1. the perf capture (bunny, 1920x1080, 8 views, K = 16..256; the dense Hermite tracer, the
#      trilinear tracer, the cells as 8x8 tiles and as boxes over proxy boxes, as boxes with
#      two-phase occlusion culling (off by default until a GPU has measured it), over whole cells,
#      then as 4x4 and 16x16 tiles), or the capture options given;
#   2. the GPU test suite, HSDF_TEST_DEVICE=gpu, validation layers on (one gtest XML per binary);
#   3. what scripts/run.sh shows (the default split screen), headless, as a PNG;
#   4. the GPU's own shader compiler statistics of every pipeline (shader_stats --native: VGPRs,
#      spills, ... where the driver has VK_KHR_pipeline_executable_properties; compiler
#      statistics, not timings), in shader_stats/.
# Everything lands under $OUT (the device tool brings it back): capture/, tests/, shader_stats/, device.txt,
# run_sh_default_split.png, and steps.txt with each step's exit status and seconds. Commit the
# capture under docs/perf/<gpu name>/ with the command that made it.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${OUT:-$here/out}
budget=${HSDF_DEVICE_SECONDS:-480}
device=${HSDF_DEVICE_KIND:-gpu}  # lavapipe: to try the script here
export HSDF_TEST_DEVICE=${HSDF_TEST_DEVICE:-$device}
mkdir -p "$out"
work=$(mktemp -d)
tar -C "$work" -xJf "$here/pack.tar.xz" || { echo "device_run: cannot unpack $here/pack.tar.xz" >&2; exit 1; }
export HSDF_COMMIT=$(cat "$work/commit")
start=$SECONDS
left() { echo $((budget - (SECONDS - start))); }
step() {  # step NAME SECONDS COMMAND...: runs it with a time limit, records rc and duration
  local name=$1 limit=$2 t0=$SECONDS rc
  shift 2
  if [ "$limit" -le 5 ]; then echo "$name: skipped (no time left)" | tee -a "$out/steps.txt"; return; fi
  timeout --kill-after=10 "$limit" "$@" > "$out/$name.log" 2>&1
  rc=$?
  echo "$name: rc=$rc, $((SECONDS - t0)) s (limit $limit s)" | tee -a "$out/steps.txt"
}

{ { nvidia-smi -L || echo "no nvidia-smi"; } 2>&1; echo "commit: $HSDF_COMMIT"; } > "$out/device.txt"
capture=("$@")
if [ ${#capture[@]} -eq 0 ]; then
  capture=(--size 1920x1080 --views 8 --frames 10 --warmup 3 --resolutions 16,32,64,128,256
           --methods hermite,trilinear,cells
           --settings "n=3 r=1 tiles,n=3 r=1 boxes,n=3 r=1 occlusion,n=3 r=1 boxes whole cells,n=3 r=1 tiles whole cells,n=3 r=1 tiles 4x4,n=3 r=1 tiles 16x16")
fi
# The tests, the screenshot and the statistics take well under two and a half minutes together: the
# capture gets the rest. Its own --time-limit stops starting rows 60 s before the step's limit, so
# that it writes its report rather than being killed (results.csv / .json are rewritten after every
# row in any case).
limit=$(( $(left) - 150 ))
case " ${capture[*]} " in *" --time-limit "*) ;; *) capture+=(--time-limit $(( limit > 120 ? limit - 60 : limit / 2 ))) ;; esac
step capture $limit "$work/gpu/run.sh" perf_capture --device "$device" --out "$out/capture" "${capture[@]}"
step tests $(( $(left) - 40 )) "$work/gpu-tests/run.sh" "$out/tests"
step split $(( $(left) - 30 )) "$work/gpu/run.sh" scene_runner --headless --ui --device "$device" --split vertical --frames 3 \
  --screenshot "$out/run_sh_default_split.png"
step shader_stats $(( $(left) )) "$work/gpu/run.sh" shader_stats --native --device "$device" --out "$out/shader_stats"
tail -n 3 "$out"/*.log

#!/usr/bin/env bash
# Here, before a session's device call: packs the release build's programs
# (../shared/tools/pack_for_gpu.sh) and GPU tests (scripts/pack_gpu_tests.sh) into one archive,
# .device/pack.tar.xz (ignored by git, well under the device tool's 64 MiB carry limit), with
# scripts/perf/device_run.sh beside it. The commit built is stamped into the archive (HSDF_COMMIT),
# since the device machine's copy of the checkout has no history to describe.
#   scripts/perf/device_pack.sh [BUILD_DIR]          (default build/release; build it first)
# Then, in one device call that carries .device:
#   bash .device/device_run.sh [capture options...]  (see device_run.sh)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build/release}" && pwd)
pack_tool=${HSDF_PACK_FOR_GPU:-$root/../shared/tools/pack_for_gpu.sh}
[ -x "$pack_tool" ] || [ -f "$pack_tool" ] || { echo "device_pack: $pack_tool not found (set HSDF_PACK_FOR_GPU)" >&2; exit 1; }
out=$root/.device
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
bash "$pack_tool" "$build" "$stage/gpu" "$root" >/dev/null
# shader_stats (the compiler statistics of every pipeline) needs no library perf_capture does not.
cp "$build/samples/shader_stats/shader_stats" "$stage/gpu/bin/" && strip "$stage/gpu/bin/shader_stats"
bash "$root/scripts/pack_gpu_tests.sh" "$build" "$stage/gpu-tests" >/dev/null
commit=$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)
echo "$commit" > "$stage/commit"
rm -rf "$out"
mkdir -p "$out"
tar -C "$stage" -cJf "$out/pack.tar.xz" gpu gpu-tests commit
cp "$root/scripts/perf/device_run.sh" "$out/"
echo "device_pack: $out/pack.tar.xz ($(du -h "$out/pack.tar.xz" | cut -f1), commit $commit)"

#!/usr/bin/env bash
# The shader compiler's statistics of every pipeline for the paper's GPU family, AMD NAVI10 (RX 5700),
# as committed under docs/perf/radv-navi10/: Mesa's RADV shows a null device of the family when
# RADV_FORCE_FAMILY is set (mesa-vulkan-drivers, no AMD GPU needed), which compiles every pipeline
# with the real ACO compiler and cannot run anything. shader_stats draws tiny frames on lavapipe so
# that every pipeline is built, and compiles each again there. Registers, spills, instructions and
# occupancy: compiler statistics, not timings. Takes well under a minute.
# Usage: scripts/perf/shader_stats.sh [build dir] [shader_stats options...]
#   (another family: RADV_FORCE_FAMILY=gfx1100 scripts/perf/shader_stats.sh build/release --statistics-device GFX1100 --out DIR)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build/release}" && pwd)
shift || true
cd "$root"  # the table names its folder as committed
source "$root/scripts/deps.sh" && hsdf_runtime_env  # a private XDG_RUNTIME_DIR, reused
export RADV_FORCE_FAMILY=${RADV_FORCE_FAMILY:-navi10}
export HSDF_COMMIT=${HSDF_COMMIT:-$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)}
# NAVI10 into the committed folder, unless the caller names another device or folder (shader_stats
# takes each option once).
statistics=(--statistics-device NAVI10) out=(--out docs/perf/radv-navi10)
for arg in "$@"; do
  [[ $arg == --statistics-device || $arg == --statistics-device=* ]] && statistics=()
  [[ $arg == --out || $arg == --out=* ]] && out=()
done
exec "$build/samples/shader_stats/shader_stats" --device lavapipe "${statistics[@]}" "${out[@]}" "$@"

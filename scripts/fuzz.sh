#!/usr/bin/env bash
# Builds the libFuzzer targets (the `fuzz` preset, clang, ASan + UBSan) and runs each for a while,
# one after the other, from a scratch copy of its seed corpus (tests/data/fuzz/<target>/):
#   scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET ...]     (default: 30 s, every target)
# Prints libFuzzer's last status line per target (executions, coverage, corpus) and exits 1 on the
# first crash, leak, timeout or FUZZ_CHECK failure; libFuzzer writes the input that did it as
# build/fuzz/artifacts/<target>/crash-* (commit it to the corpus with the fix). Without clang the
# script says so and exits 0: the corpus replays (<target>_replay ctests) still run in every build.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
seconds=${1:-30}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for dir in tests/data/fuzz/*/; do targets+=("$(basename "$dir")"); done
fi
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found: libFuzzer targets not built (the corpus replays still run)"
  exit 0
fi
cmake --preset fuzz -DHSDF_BUILD_GPU_TESTS=OFF >/dev/null
cmake --build --preset fuzz -j "$(nproc)" --target "${targets[@]}"
for target in "${targets[@]}"; do
  work=build/fuzz/corpus/$target
  artifacts=build/fuzz/artifacts/$target
  mkdir -p "$work" "$artifacts"
  cp -n tests/data/fuzz/"$target"/* "$work"/
  log=build/fuzz/$target.log
  echo "== $target: ${seconds} s"
  # -max_len: the largest seed is a few KB; longer inputs only slow the loaders down.
  # -timeout: one input taking 10 s is a hang (the replay ctests take a few ms an input).
  if ! UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
      build/fuzz/tests/fuzz/"$target" "$work" -max_total_time="$seconds" -max_len=8192 -timeout=10 \
      -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1; then
    tail -40 "$log"
    echo "fuzz.sh: $target failed; the input is in $artifacts/"
    exit 1
  fi
  grep -E '^#[0-9]+' "$log" | tail -1
  grep -E 'stat::number_of_executed_units|stat::peak_rss_mb' "$log"
done

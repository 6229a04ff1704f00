#!/usr/bin/env bash
# Packs the GPU test suite of a release build into one folder that runs on another x86-64 Linux
# machine with a Vulkan driver but none of Debian's packages (the device machines lent to some
# sessions: they cannot install or build anything). What ../shared/tools/pack_for_gpu.sh does for
# the programs, for the tests: the gtest binaries of tests/gpu and the Viewer's GPU tests
# (tests/unit/samples: the frame step the programs share), their SPIR-V, sample assets and test
# data (tests/data), every
# shared library they need except glibc/libstdc++/libgcc (the target's are newer), the Vulkan loader
# and Khronos validation layer (the tests fail on any validation message, on every device).
#   scripts/pack_gpu_tests.sh [BUILD_DIR] [OUT_DIR]     (default build/release .gpu-tests)
# On the target:  OUT_DIR/run.sh [RESULTS_DIR] [gtest filter]
# runs every binary with HSDF_TEST_DEVICE=gpu (override it to run elsewhere), writes one gtest
# XML report per binary to RESULTS_DIR (default $OUT or ./results) and exits non-zero on a failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build/release}" && pwd)
out=${2:-$root/.gpu-tests}
rm -rf "$out"
mkdir -p "$out/bin" "$out/lib" "$out/shaders" "$out/assets" "$out/data" "$out/layers"

tests=()
for t in "$build"/tests/gpu/*_tests "$build"/tests/unit/samples/sample_viewer_gpu_tests \
         "$build"/tests/unit/samples/sample_viewer_fault_tests; do
  [ -x "$t" ] && tests+=("$t")
done
[ ${#tests[@]} -gt 0 ] || { echo "pack_gpu_tests: no GPU test binaries under $build/tests/gpu (build first)" >&2; exit 1; }
for t in "${tests[@]}"; do cp "$t" "$out/bin/"; strip "$out/bin/$(basename "$t")"; done
cp "$build"/shaders/*.spv "$out/shaders/"
cp "$root"/samples/assets/*.gl* "$out/assets/"
cp -r "$root"/tests/data/. "$out/data/"

# Libraries: what the tests link, and what the validation layer links.
layer_so=$(ldconfig -p | awk '$1 == "libVkLayer_khronos_validation.so" && /x86-64/ {print $NF; exit}')
layer_json=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
[ -n "$layer_so" ] && [ -f "$layer_json" ] || { echo "pack_gpu_tests: the Khronos validation layer is not installed (vulkan-validationlayers)" >&2; exit 1; }
cp -L "$layer_so" "$out/layers/"
# The manifest's library_path is relative to the manifest: the copy beside it.
sed 's|"library_path": *"[^"]*"|"library_path": "./libVkLayer_khronos_validation.so"|' "$layer_json" > "$out/layers/VkLayer_khronos_validation.json"
skip='^(linux-vdso|ld-linux|libc\.so|libm\.so|libstdc\+\+|libgcc_s|libdl\.so|libpthread|librt\.so)'
for b in "$out"/bin/* "$out/layers/libVkLayer_khronos_validation.so"; do
  ldd "$b" | awk '$3 ~ /^\// {print $1, $3}' | while read -r name path; do
    [[ $name =~ $skip ]] || cp -L "$path" "$out/lib/$name"
  done
done
# The vendor-neutral GL dispatch libraries: some GPU drivers' Vulkan ICDs load them.
for name in libGLdispatch.so.0 libGLX.so.0 libEGL.so.1 libGL.so.1 libOpenGL.so.0 libGLESv2.so.2; do
  path=$(ldconfig -p | awk -v n="$name" '$1 == n && /x86-64/ {print $NF; exit}')
  [ -n "$path" ] && cp -L "$path" "$out/lib/$name"
done

cat > "$out/run.sh" <<'RUN'
#!/usr/bin/env bash
# Runs the packed GPU tests on this machine's GPU (HSDF_TEST_DEVICE, default gpu), validation on.
#   run.sh [RESULTS_DIR] [gtest filter]
here=$(cd "$(dirname "$0")" && pwd)
results=${1:-${OUT:-$here/results}}
filter=${2:-*}
mkdir -p "$results"
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export HSDF_SHADER_DIR="$here/shaders" HSDF_ASSET_DIR="$here/assets" HSDF_TEST_DATA_DIR="$here/data"
export HSDF_TEST_DEVICE=${HSDF_TEST_DEVICE:-gpu}
export VK_ADD_LAYER_PATH="$here/layers${VK_ADD_LAYER_PATH:+:$VK_ADD_LAYER_PATH}"
# One folder per user, reused by every call (a mktemp folder per call was never removed).
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="${TMPDIR:-/tmp}/hsdf-xdg-$(id -u)"
  { mkdir -p "$XDG_RUNTIME_DIR" 2>/dev/null && [ -O "$XDG_RUNTIME_DIR" ]; } || XDG_RUNTIME_DIR=$(mktemp -d)
  chmod 700 "$XDG_RUNTIME_DIR"
fi
# A driver installed outside the loader's search path (some containers): point the loader at it.
for icd in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json; do
  [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$icd" ] && [ ! -f /usr/share/vulkan/icd.d/nvidia_icd.json ] && export VK_DRIVER_FILES=$icd
done
status=0
for t in "$here"/bin/*; do
  name=$(basename "$t")
  echo "== $name (HSDF_TEST_DEVICE=$HSDF_TEST_DEVICE)"
  "$t" --gtest_filter="$filter" --gtest_output="xml:$results/$name.xml" > "$results/$name.log" 2>&1 || status=1
  grep -E '^\[  (PASSED|FAILED|SKIPPED) ' "$results/$name.log" | sed 's/^/   /'
done
echo "results in $results (one .xml and .log per binary); exit $status"
exit $status
RUN
chmod +x "$out/run.sh"
du -sh "$out" | awk '{print "packed " $1 " into " $2}'

#!/usr/bin/env bash
# The tuning panel's controls, driven by panel_script.txt through --script (the TuningState path
# the panel uses) in a real GLFW window under Xvfb, validation on (a message fails the run).
# Checks what would break if a control stopped working: the object is drawn after every change,
# a completed re-bake changes the stored scalars and a cancelled or over-budget one keeps the old
# K, each method and debug view changes the image, the panel is drawn, the resize reaches the
# swapchain, the settings sidecar and the settings round trip hold the tuning, full screen follows
# the screen and back, the fly camera starts at the orbit camera's view, the split screen shows the
# compared method on its side in both orientations, the difference view reports a non-zero angle,
# a shader reload rebuilds the pipelines without changing the image, a reload from a broken SPIR-V
# file keeps the old pipelines (same image) and names the file, and the compared side's normals mode
# changes only its side.
# Exit 77 (ctest: skipped) when Xvfb is not installed.
set -u
runner=$1 probe=$2 script=$3 work=$4 shaders=$5
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIPPED: xvfb-run not found (Debian package xvfb); the panel script was not run"
  exit 77
fi
source "$(cd "$(dirname "$0")" && pwd)/xvfb_checks.sh" || exit 1
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
# Two copies of the build's SPIR-V for the reloads (shader-dir=): spv/ as built, spv_broken/ with
# cells_resolve.frag.spv cut to its first half (whole words: only the loader's instruction walk
# sees it, the size and header checks pass).
cp -r "$shaders" spv && cp -r "$shaders" spv_broken || fail "cannot copy the shaders from $shaders"
spv_words=$(( $(stat -c %s spv/cells_resolve.frag.spv) / 8 ))
head -c $(( spv_words * 4 )) spv/cells_resolve.frag.spv >spv_broken/cells_resolve.frag.spv
in_xvfb 300 "$runner" --validation --no-ground --size 128x96 --resolution 24 \
  --bake-budget-mib 16 --ui-ini "" --script "$script" --frames 46 >log.txt 2>&1
rc=$?
cat log.txt
[ $rc -eq 0 ] || fail "scene_runner exited with $rc"

# The object is drawn (the ground is off, the panel hidden: the rest is background).
for png in cells_k24 cells_k40 cancelled trilinear hermite mesh cells_n1 view_normals view_depth view_cells \
           view_evals view_wireframe resized reloaded; do
  drawn $png
done

# Each change reaches the image: compared with the cells at the same K (40). Dense Hermite sphere
# tracing draws the same interpolant as the cells (a few edge pixels differ): it is compared with
# trilinear instead.
d=$(FIELD=differs field hermite.png trilinear.png)
at_least "$d" 0.005 || fail "hermite.png looks like trilinear.png (differs $d): the method did not change"
for png in trilinear mesh cells_n1 view_normals view_depth view_cells view_evals view_wireframe panel; do
  d=$(FIELD=differs field $png.png cells_k40.png)
  at_least "$d" 0.005 || fail "$png.png looks like cells_k40.png (differs $d): the setting did not reach the frame"
done

# Re-bakes: the completed one changes the stored scalars; the cancelled and the refused ones keep K 40.
scalars() { grep "screenshot: $1.png" log.txt | sed -n 's/.*stored scalars: cells \([0-9]*\).*/\1/p'; }
s24=$(scalars cells_k24) s40=$(scalars cells_k40)
[ -n "$s24" ] && [ -n "$s40" ] || fail "no stored-scalar count logged with the screenshots"
[ "$s24" != "$s40" ] || fail "re-baking K 24 -> 40 left the stored scalars at $s24"
grep -q "screenshot: cancelled.png .*K 40:" log.txt || fail "the cancelled re-bake did not keep K 40"
grep -q "re-baking at resolution 56: .*cancelled" log.txt || fail "the cancelled re-bake was not reported"
grep -q "re-baking at resolution 256: .*over the bake budget" log.txt || fail "the bake past the budget was not refused"
grep -q "screenshot: trilinear.png .*K 40:" log.txt || fail "K after the refused bake is not the drawn 40"

# The sidecar is a settings file of the screenshot's tuning.
grep -q '"method": "trilinear"' trilinear.json || fail "trilinear.json does not hold the method"
grep -q '"debug_view": "depth"' view_depth.json || fail "view_depth.json does not hold the debug view"

# Resize: the swapchain and the render targets follow the window.
size_is cells_k40 128x96
size_is resized 160x112
# load-settings brings back the saved tuning (method cells, not the trilinear set just before).
grep -q '"method": "cells"' reloaded.json || fail "load-settings did not restore the method"
same reloaded resized
# Full screen: the swapchain follows the screen and then the window again.
size_is fullscreen 640x480
size_is windowed_again 160x112
# The fly camera takes over the orbit camera's view (a few edge pixels may round differently).
d=$(FIELD=differs field fly.png windowed_again.png)
at_least 0.01 "$d" || fail "fly.png differs from windowed_again.png in $d of the pixels: switching cameras moved the view"
# Certified roots reach the cell shader: the evaluation counts change, the object stays.
drawn certified
d=$(FIELD=differs field evals_certified.png evals_plain.png)
at_least "$d" 0.005 || fail "evals_certified.png looks like evals_plain.png (differs $d): certified did not reach the shader"
# Split screen: one side is the trilinear frame (differs from the cells one), both orientations
# draw, and the log names what was compared.
for png in split_vertical split_horizontal difference; do
  drawn $png
  d=$(FIELD=differs field $png.png cells_ref.png)
  at_least "$d" 0.005 || fail "$png.png looks like cells_ref.png (differs $d): the comparison did not reach the frame"
done
d=$(FIELD=differs field split_horizontal.png split_vertical.png)
at_least "$d" 0.005 || fail "split_horizontal.png looks like split_vertical.png (differs $d)"
grep -q "split_vertical.png: split vertical at 0.50: cells K 40 | trilinear K 48" log.txt || fail "the vertical split did not compare cells K 40 with trilinear K 48"
grep -q "split_horizontal.png: split horizontal at 0.30" log.txt || fail "the horizontal split was not drawn at 0.30"
mean=$(sed -n 's/.*difference.png: difference cells vs trilinear: mean \([0-9.]*\) deg.*/\1/p' log.txt)
[ -n "$mean" ] || fail "the difference view reported no numbers"
at_least "$mean" 0.1 || fail "the difference view reports a mean angle of $mean degrees between cells and trilinear"
# Reload: every feature that can reload did, and the image is the same.
grep -q "meshes: reloaded" log.txt && grep -q "sphere tracing: reloaded" log.txt || fail "the shader reload was not reported"
same after_reload cells_ref "reloading the same shaders changed the image"
# The broken reload: the cells feature refused the cut file (the loader's message names it, in the
# log and in the panel's report), the other features reloaded, and the frame is the one before.
grep -q "hermite cells: shader spv_broken/cells_resolve.frag.spv: not SPIR-V (truncated" log.txt ||
  fail "the broken cells_resolve.frag.spv was not refused with the file named"
grep -A3 "reload-shaders: panel report" log.txt | grep -q "spv_broken/cells_resolve.frag.spv: not SPIR-V (truncated" ||
  fail "the panel's reload report does not hold the loader's message"
grep -q "\[warning\] shaders from .*spv_broken: 1 of [0-9]* features kept their old pipelines" log.txt ||
  fail "the broken reload was not logged as a warning naming how many features kept their pipelines"
same broken_reload after_reload "the failed reload changed the image"
# The good reload after it: every feature reloaded (the last cells line says so), same image.
last_cells=$(grep "^hermite cells: " log.txt | tail -1)
[ "$last_cells" = "hermite cells: reloaded" ] || fail "the reload after the broken one did not reload the cells: $last_cells"
same good_reload cells_ref
# The compared side's normals: the log names exact for it, the cells half (left of the divider at
# 80 of 160) is unchanged and the trilinear half changed.
grep -q "split_vertical.png: split vertical at 0.50: .*(central normals)" log.txt || fail "the first split did not use central normals"
grep -q "split_exact_normals.png: split vertical at 0.50: cells K 40 | trilinear K 48 (exact normals)" log.txt ||
  fail "compare_normals=exact did not reach the compared side"
d=$(FIELD=differs field --crop 0,0,80,112 split_exact_normals.png split_vertical.png)
[ "$d" = 0.0000 ] || fail "the cells side changed ($d) when only the compared side's normals did"
d=$(FIELD=differs field --crop 80,0,80,112 split_exact_normals.png split_vertical.png)
at_least "$d" 0.005 || fail "the trilinear side looks the same with exact normals (differs $d)"
# Levels of detail: the levels were baked from the scene's source, and the object is still drawn.
grep -q "levels of detail: 2 levels from K = 40" log.txt || fail "lod=true did not bake the levels of K 40"
grep -q "screenshot: lod.png (160x112, cells; K 20:" log.txt || fail "lod.png was not drawn from the K 20 level"
drawn lod
echo "panel script: all checks passed"

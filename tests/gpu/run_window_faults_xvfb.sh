#!/usr/bin/env bash
# Window faults driven by window_faults_script.txt in a real GLFW window under Xvfb,
# validation on (a message fails the run): minimise and restore, a resize storm down to 1x1, the
# split screen in a 1-pixel-wide window, a resize while minimised, presents that report out of date
# and suboptimal. X11 iconifies a window through
# the window manager, so openbox runs in the Xvfb display (scripts/deps.sh installs it for tests).
# Checks what would break if the loop mishandled a fault: the run ends cleanly, the minimised steps
# draw nothing and are reported, every frame after a fault has the window's size and shows the
# object, the tiny sizes reached the swapchain, and images at equal settings are equal.
# Exit 77 (ctest: skipped) when Xvfb or openbox is not installed.
set -u
runner=$1 probe=$2 script=$3 work=$4
for tool in xvfb-run openbox xprop; do
  if ! command -v $tool >/dev/null 2>&1; then
    echo "SKIPPED: $tool not found (Debian packages xvfb, openbox, x11-utils); the window faults were not run"
    exit 77
  fi
done
source "$(cd "$(dirname "$0")" && pwd)/xvfb_checks.sh" || exit 1
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1

# In the display: openbox first, the runner once openbox has claimed the screen (the root window's
# _NET_SUPPORTING_WM_CHECK), then openbox is stopped.
cat >session.sh <<'SESSION'
openbox --sm-disable >openbox.log 2>&1 &
wm=$!
for i in $(seq 50); do xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | grep -q "window id" && break; sleep 0.1; done
"$@"
rc=$?
kill $wm
exit $rc
SESSION
HSDF_LOG=debug in_xvfb 300 bash session.sh "$runner" --validation --no-ground \
  --size 128x96 --resolution 24 --ui-ini "" --script "$script" --frames 35 >log.txt 2>&1
rc=$?
cat log.txt
[ $rc -eq 0 ] || fail "scene_runner exited with $rc"

# Minimise: the four steps while minimised drew nothing (a 0x0 or stale swapchain would have
# failed validation or crashed), and the frame after restoring is the frame before.
grep -q "window minimised" log.txt || fail "the minimised window was not noticed"
grep -q "window restored after 4 step(s) without a frame" log.txt || fail "the minimised steps were not 4 steps without a frame"
size_is before 128x96; size_is restored 128x96
drawn before; drawn restored
same restored before
# The smallest windows are drawn at their size (a screenshot has the renderer's extent, the swapchain's).
size_is tiny_1x1 1x1; size_is tiny_1x64 1x64; size_is tiny_64x1 64x1
# The storm: sizes reached the swapchain (the window manager may merge a few requests), the last
# size holds and the object is drawn.
n=$(awk '/script frame 10: size/ {on = 1} /script frame 26:/ {on = 0} on && /swapchain recreated: /' log.txt | wc -l)
at_least "$n" 5 || fail "only $n swapchain recreations in a storm of 14 sizes"
storm_outdated=$(awk '/script frame 10: size/ {on = 1} /script frame 26:/ {on = 0} on && /out of date or suboptimal/' log.txt | wc -l)
echo "storm: $n swapchain recreations, $storm_outdated presents out of date or suboptimal"
size_is after_storm 144x100; drawn after_storm
# One side of the split is empty in a 1-pixel-wide window; afterwards the frame is the one before.
size_is split_1px 1x40
size_is after_split 144x100; drawn after_split
same after_split after_storm
# Resized while minimised: the first frame after restoring has the new size.
size_is restored_resized 112x80; drawn restored_resized
# Out of date and suboptimal presents: each one recreated the swapchain, the frame is unchanged.
n=$(awk '/script frame 35: present-fault/ {on = 1} on && /out of date or suboptimal: recreating/' log.txt | wc -l)
[ "$n" = 2 ] || fail "$n presents were out of date or suboptimal after the 2 injected faults, not 2"
size_is after_present_faults 112x80
same after_present_faults restored_resized
# The V-sync switch while minimised at the same size: the swapchain was recreated after restoring.
n=$(awk '/script frame 41: restore/ {on = 1} on && /swapchain recreated: 112x80/' log.txt | wc -l)
[ "$n" -ge 1 ] || fail "switching V-sync while minimised never recreated the swapchain after restoring"
grep -q "window restored after 2 step(s) without a frame" log.txt || fail "the third minimised spell was not 2 steps"
size_is vsync_restored 112x80
same vsync_restored after_present_faults
grep -q "window: .* frames drawn" log.txt || fail "the run's window summary is missing"
echo "window faults: all checks passed"

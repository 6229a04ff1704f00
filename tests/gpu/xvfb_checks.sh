# Shared by the Xvfb ctests (run_*_xvfb.sh): running the scene runner in Xvfb and checking its
# screenshots and log. Sourced; the checks of images need $probe (the png_probe binary) and run in
# the test's work directory.
# Each check ends the test with "FAIL: ..." naming the file and what was wrong.

fail() { echo "FAIL: $*"; exit 1; }
# in_xvfb SECONDS COMMAND...: runs COMMAND in a fresh 640x480 Xvfb display, killed after SECONDS;
# the status is COMMAND's (124 on the time limit). The X authority file is one of ours: with its
# own temporary directory, xvfb-run sometimes fails to remove it when the server exits (1 run in
# 25 of scene_runner_failed_frame_xvfb here) and exits with 5 instead of the command's status.
in_xvfb() {
  local limit=$1 auth rc
  shift
  auth=$(mktemp "${TMPDIR:-/tmp}/hsdf_xauth.XXXXXX") || fail "cannot make an X authority file"
  timeout "$limit" xvfb-run -a -f "$auth" -s "-screen 0 640x480x24" "$@"
  rc=$?
  rm -f "$auth" "$auth"-?  # and xauth's lock files, if any were left
  return $rc
}
# png_probe's report of one image (or, with two, their difference); a probe that fails fails the test.
probe() { "$probe" "$@" || fail "png_probe $*"; }
# One field of png_probe's report ("size", "coverage", "differs"), the key in $FIELD:
# FIELD=coverage field a.png
field() { probe "$@" | awk -v key="$FIELD" '{for (i = 1; i < NF; ++i) if ($i == key) print $(i + 1)}'; }
at_least() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a >= b) }'; }
# NAME.png has the size WxH (a screenshot has the renderer's extent, so the swapchain's).
size_is() { [ "$(FIELD=size field $1.png)" = "$2" ] || fail "$1.png is $(FIELD=size field $1.png), not $2"; }
# NAME.png was written and the object covers at least 5 % of it (the ground is off, the panel
# hidden: the rest is background).
drawn() {
  [ -s $1.png ] || fail "$1.png was not written"
  local c; c=$(FIELD=coverage field $1.png)
  at_least "$c" 0.05 || fail "$1.png: the object covers only $c of the image"
}
# A.png and B.png are equal pixel for pixel; WHY (optional) says what a difference would mean.
same() {
  local d; d=$(FIELD=differs field $1.png $2.png)
  [ "$d" = 0.0000 ] || fail "$1.png differs from $2.png in $d of the pixels: ${3:-they should be equal (same settings and size)}"
}

# Checks of the scene runner's screenshots and log, shared by the Xvfb ctests (run_*_xvfb.sh):
# sourced after the test has set $probe (the png_probe binary) and entered its work directory.
# Each check ends the test with "FAIL: ..." naming the file and what was wrong.

fail() { echo "FAIL: $*"; exit 1; }
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

#!/bin/sh
# view.sh — `bvox view` end to end in the real SDL2 window under Xvfb: a
# script (tests/data/view/edit.txt) turns the object, moves the light, cuts
# and removes voxels with the brush, then saves. Checked: the screenshots
# differ from each other as they should (a turn moves the silhouette; a light
# change keeps every object pixel in place but changes their shades; the cut
# face is tinted; the brush changes only pixels near the click), they match
# the golden images in tests/data/view/ within a tolerance (BVOX_UPDATE_GOLDEN=1
# rewrites them and fails), the window shows
# exactly the canvas (the same script off screen gives identical pictures),
# and the saved model holds exactly the voxels the script left: the model cut
# at z >= 31 minus the brush ball around the voxel the click picked, which
# must be the first voxel under the click (computed here from the raw bytes,
# and again with `bvox edit` + `bvox csg`). The desktop: a real resize and a
# dropped file (SDL's drop event). Also: usage errors (exit 2), no
# display (exit 1, clear message), a bad script (exit 1, its line), --bench.
# Skipped (exit 77) only when xvfb-run is missing: scripts/install-deps.sh
# installs it.
# Usage: sh view.sh BVOX DATADIR
set -eu
BVOX=$1
DATA=$2
here=$(dirname "$0")
if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "SKIP: xvfb-run is missing (apt-get install xvfb xauth; see scripts/install-deps.sh)"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
pngtool="$here/pngtool.py"
case "$pngtool" in /*) ;; *) pngtool="$PWD/$pngtool" ;; esac
case "$BVOX" in /*) ;; *) BVOX="$PWD/$BVOX" ;; esac
case "$DATA" in /*) ;; *) DATA="$PWD/$DATA" ;; esac

# usage errors
"$BVOX" view --help | grep -q "script FILE" || fail "view --help"
set +e
"$BVOX" view >/dev/null 2>&1; [ $? -eq 2 ] || fail "view without MODEL must exit 2"
"$BVOX" view --demo --offscreen >/dev/null 2>&1; [ $? -eq 2 ] || fail "--offscreen without --script must exit 2"
"$BVOX" view --demo --size 10,10 >/dev/null 2>&1; [ $? -eq 2 ] || fail "--size 10,10 must exit 2"
"$BVOX" view --demo --lut x.txt >/dev/null 2>&1; [ $? -eq 2 ] || fail "--lut without --labels must exit 2"
"$BVOX" view --demo --labels >/dev/null 2>&1; [ $? -eq 2 ] || fail "--labels with --demo must exit 2"
set -e

# the model: a ball and a bar along +x (not symmetric, so a turn shows)
"$BVOX" csg "sphere(r=18, at=31.5,31.5,31.5) + box(min=40,28,28, max=58,35,35)" \
    --dims 64,64,64 -o "$tmp/ball.nii" >/dev/null || fail "making the model"
"$BVOX" convert "$tmp/ball.nii" "$tmp/ball.raw" >/dev/null || fail "raw copy"

# no display: a clear message, exit 1
set +e
(unset DISPLAY WAYLAND_DISPLAY; SDL_VIDEODRIVER= "$BVOX" view "$tmp/ball.nii" >"$tmp/nodisp.out" 2>&1)
rc=$?
set -e
[ $rc -eq 1 ] || fail "without a display view must exit 1 (got $rc)"
grep -q "cannot open a window" "$tmp/nodisp.out" || fail "no clear message without a display: $(cat "$tmp/nodisp.out")"

# inx NAME CMD...: run CMD on a fresh X server (xvfb-run), its exit status
# into a file (xvfb-run's own status also reports its clean-up, which can
# race with a program that exits at once). In a sanitizer build the X11 and
# D-Bus libraries SDL loads leak at exit (not our code, and unloaded before
# LeakSanitizer can name them): window runs do not check leaks; the
# off-screen run of the same script below does, for all of the viewer but
# the SDL calls of present.c.
inx() { # inx NAME CMD...: stdout, stderr and status in $tmp/NAME.{out,err,rc}
    name=$tmp/$1
    shift
    ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" xvfb-run -a -s "-screen 0 640x480x24" \
        sh -c 'n=$0; echo "$XAUTHORITY" >"$n.auth"; "$@" >"$n.out" 2>"$n.err"; echo $? >"$n.rc"' \
        "$name" "$@" || true
    # xvfb-run's clean-up can fail (a race in its script: exit 5) before it
    # stops its X server: stop that server, known by its own auth file
    if [ -s "$name.auth" ]; then
        auth=$(cat "$name.auth")
        for p in /proc/[0-9]*; do
            if tr '\0' ' ' <"$p/cmdline" 2>/dev/null | grep -qF -- "-auth $auth"; then
                kill "${p#/proc/}" 2>/dev/null || true
            fi
        done
    fi
    [ -s "$name.rc" ] || fail "xvfb-run did not run the viewer"
}

# --labels with a table that is not there: exit 1, one clear line, no window
set +e
(unset DISPLAY WAYLAND_DISPLAY; "$BVOX" view "$tmp/ball.nii" --labels --lut "$tmp/no-such-lut.txt" >"$tmp/lut.out" 2>&1)
rc=$?
set -e
[ $rc -eq 1 ] || fail "--labels with a missing --lut must exit 1 (got $rc)"
grep -q "^bvox: .*no-such-lut.txt" "$tmp/lut.out" || fail "no clear message for a missing table: $(cat "$tmp/lut.out")"

# a bad script: exit 1 naming the line, before any window opens (no display here)
printf 'key 5\njump 3 4\n' >"$tmp/bad.txt"
set +e
(unset DISPLAY WAYLAND_DISPLAY; "$BVOX" view "$tmp/ball.nii" --script "$tmp/bad.txt" >"$tmp/bad.out" 2>&1)
rc=$?
set -e
[ $rc -eq 1 ] || fail "a bad script must exit 1 (got $rc)"
grep -q "script line 2" "$tmp/bad.out" || fail "the bad line is not named: $(cat "$tmp/bad.out")"
grep -q "cannot open a window" "$tmp/bad.out" && fail "the script must be checked before the window opens"

# the script, in the window and off screen
mkdir "$tmp/win" "$tmp/off"
(cd "$tmp/win" && inx win "$BVOX" view "$tmp/ball.nii" --script "$DATA/view/edit.txt" --size 320,320)
[ "$(cat "$tmp/win.rc")" -eq 0 ] || fail "the script failed in the window: $(cat "$tmp/win.err")"
cp "$tmp/win.out" "$tmp/win/log.txt"
(cd "$tmp/off" && "$BVOX" view "$tmp/ball.nii" --script "$DATA/view/edit.txt" \
    --size 320,320 --offscreen >log.txt 2>err.txt) || fail "the script failed off screen: $(cat "$tmp/off/err.txt")"
for f in s0 s1 s2 s3 s4 s5; do
    [ -f "$tmp/win/$f.png" ] || fail "no screenshot $f.png"
done
grep -q "view: brush remove r=3 at" "$tmp/win/log.txt" || fail "no brush edit logged"
grep -q "view: saved edited.nii" "$tmp/win/log.txt" || fail "no save logged"

# the saved model, against the raw bytes (here) and against bvox edit + csg
hit=$(sed -n 's/^view: brush remove r=3 at \([0-9]*,[0-9]*,[0-9]*\)$/\1/p' "$tmp/win/log.txt")
[ -n "$hit" ] || fail "no brush position logged"
"$BVOX" convert "$tmp/win/edited.nii" "$tmp/edited.raw" >/dev/null || fail "reading the saved model"
"$BVOX" edit "$tmp/ball.nii" -o "$tmp/cut.nii" --keep-above 0,0,1,-30.5 >/dev/null || fail "bvox edit"
"$BVOX" csg "$tmp/cut.nii - sphere(r=3, at=$hit)" -o "$tmp/ref.nii" >/dev/null || fail "bvox csg"
"$BVOX" convert "$tmp/ref.nii" "$tmp/ref.raw" >/dev/null || fail "raw of the reference"
python3 - "$tmp/ball.raw" "$tmp/edited.raw" "$tmp/ref.raw" "$hit" <<'PY' || fail "the saved model is not the edited one"
import sys
n = 64
orig, got, ref = (open(p, "rb").read() for p in sys.argv[1:4])
hx, hy, hz = map(int, sys.argv[4].split(","))
at = lambda x, y, z: (z * n + y) * n + x
# the cut kept z >= 31; the click, 3 pixels right and down of the centre of
# the +z view (the bounding box centre: x 36, y 31.5), picks the first voxel
# of its column
assert hz == 31, ("the brush did not start on the cut face", hz)
assert abs(hx - 36) <= 4 and abs(hy - 31.5) <= 4, ("the click is not near the centre", hx, hy)
assert orig[at(hx, hy, hz)] and not any(orig[at(hx, hy, z)] and z >= 31 and z < hz for z in range(n))
want = bytearray(n * n * n)
for z in range(31, n):
    for y in range(n):
        for x in range(n):
            i = at(x, y, z)
            if orig[i] and (x - hx) ** 2 + (y - hy) ** 2 + (z - hz) ** 2 > 9:
                want[i] = 1
removed = sum(orig) - sum(want)
assert bytes(want) == got, "saved model differs from the expected one"
assert got == ref, "saved model differs from bvox edit + bvox csg"
assert removed > 10000, removed
print("saved model: exact (%d voxels removed)" % removed)
PY

# the pictures; goldens in $DATA/view (or $BVOX_GOLDEN_DIR/view). With
# BVOX_UPDATE_GOLDEN=1 the goldens are rewritten from this run and the test
# FAILS on purpose: look at them, commit them, run again without it.
golden_dir=${BVOX_GOLDEN_DIR:-$DATA}/view
update=${BVOX_UPDATE_GOLDEN:-0}
[ -n "$update" ] || update=0
set +e
python3 - "$pngtool" "$tmp/win" "$tmp/off" "$golden_dir" "$update" <<'PY'
import json, shutil, subprocess, sys
tool, win, off, gold, update = sys.argv[1:6]
def load(path):
    g = json.loads(subprocess.check_output([sys.executable, tool, "read", path]))
    assert (g["width"], g["height"], g["channels"], g["bits"]) == (320, 320, 3, 8), path
    return [tuple(r[i:i + 3]) for r in g["rows"] for i in range(0, len(r), 3)]
BG = (22, 26, 34)
TOP = 56 * 320  # the overlay's rows are left out of the comparisons between shots
shots = {k: load("%s/%s.png" % (win, k)) for k in ("s0", "s1", "s2", "s3", "s4", "s5")}
for k, px in shots.items():  # the window shows exactly the canvas
    assert px == load("%s/%s.png" % (off, k)), "window and canvas differ in " + k
def mask(px): return [p != BG for p in px[TOP:]]
m0, m1, m2 = mask(shots["s0"]), mask(shots["s1"]), mask(shots["s2"])
moved = sum(a != b for a, b in zip(m0, m1))
assert moved > 0.02 * len(m0), ("the turn did not move the silhouette", moved)
assert m1 == m2, "a light change moved object pixels"
obj = [i for i, b in enumerate(m1) if b]
relit = sum(shots["s1"][TOP + i] != shots["s2"][TOP + i] for i in obj)
assert relit > 0.3 * len(obj), ("the light change did not relight", relit, len(obj))
orange = lambda px: sum(1 for r, g, b in px[TOP:] if r > g + 30 and g > b + 30)
assert orange(shots["s2"]) == 0 and orange(shots["s3"]) > 1000, (orange(shots["s2"]), orange(shots["s3"]))
diff = [i for i in range(TOP, 320 * 320) if shots["s4"][i] != shots["s5"][i]]
assert len(diff) > 30, ("the brush changed nothing on screen", len(diff))
far = [i for i in diff if (i % 320 - 163) ** 2 + (i // 320 - 163) ** 2 > 45 ** 2]
assert not far, ("the brush changed pixels far from the click", len(far))
if update != "0":  # rewrite the goldens from this run, then fail (exit 3)
    for k in ("s1", "s2", "s3", "s5"):
        shutil.copyfile("%s/%s.png" % (win, k), "%s/%s.png" % (gold, k))
        print("golden %s/%s.png updated; inspect and commit it, then re-run without "
              "BVOX_UPDATE_GOLDEN" % (gold, k), file=sys.stderr)
    sys.exit(3)
for k in ("s1", "s2", "s3", "s5"):  # golden images, looked at once
    g = load("%s/%s.png" % (gold, k))
    d = [max(abs(a - b) for a, b in zip(p, q)) for p, q in zip(shots[k], g)]
    big = sum(1 for x in d if x > 24)
    mean = sum(d) / len(d)
    assert mean <= 1.0 and big <= 0.005 * len(d), (k, "differs from its golden image", mean, big)
print("screenshots: as expected")
PY
rc=$?
set -e
[ $rc -ne 3 ] || fail "goldens updated (BVOX_UPDATE_GOLDEN): this run fails on purpose"
[ $rc -eq 0 ] || fail "the screenshots are not as expected"

# the desktop: the window resized by the window system (the script asks it
# for 400x300; the viewer follows the size event it sends) and a file
# dropped on it (SDL's own drop event): the screenshots, read back from the
# window, have the new size and equal the off-screen canvas; the dropped
# model replaces the ball (logged, another silhouette).
"$BVOX" csg "box(min=10,20,5, max=50,40,60)" --dims 64,64,64 -o "$tmp/other.nii" >/dev/null ||
    fail "making the model to drop"
printf 'screenshot d0.png\nresize 400 300\nscreenshot d1.png\ndrop %s\nscreenshot d2.png\nkey g\n' \
    "$tmp/other.nii" >"$tmp/desk.txt"
mkdir "$tmp/dwin" "$tmp/doff"
(cd "$tmp/dwin" && inx desk "$BVOX" view "$tmp/ball.nii" --script "$tmp/desk.txt" --size 320,320)
[ "$(cat "$tmp/desk.rc")" -eq 0 ] || fail "the desktop script failed in the window: $(cat "$tmp/desk.err")"
(cd "$tmp/doff" && "$BVOX" view "$tmp/ball.nii" --script "$tmp/desk.txt" --size 320,320 \
    --offscreen >log.txt 2>err.txt) || fail "the desktop script failed off screen: $(cat "$tmp/doff/err.txt")"
ocount=$("$BVOX" info "$tmp/other.nii" | sed -n 's/^count: *\([0-9]*\) voxels.*/\1/p')
grep -q "^view: opened $tmp/other.nii (64x64x64, $ocount voxels)$" "$tmp/desk.out" ||
    fail "the drop did not open the file: $(cat "$tmp/desk.out")"
python3 - "$pngtool" "$tmp/dwin" "$tmp/doff" <<'PY' || fail "the desktop screenshots"
import json, subprocess, sys
tool, win, off = sys.argv[1:4]
def load(path):
    g = json.loads(subprocess.check_output([sys.executable, tool, "read", path]))
    return g["width"], g["height"], g["rows"]
sizes = {}
for k in ("d0", "d1", "d2"):
    w = load("%s/%s.png" % (win, k))
    assert w == load("%s/%s.png" % (off, k)), "window and canvas differ in " + k
    sizes[k] = w[:2]
assert sizes == {"d0": (320, 320), "d1": (400, 300), "d2": (400, 300)}, sizes
# below the overlay: the ball and the box differ
a, b = load("%s/d1.png" % win)[2], load("%s/d2.png" % win)[2]
diff = sum(1 for y in range(80, 300) for x in range(400 * 3) if a[y][x] != b[y][x])
assert diff > 3000, ("the dropped model looks like the old one", diff)
print("desktop: resize and drop as expected")
PY

# the benchmark runs off screen and prints the rate
"$BVOX" view "$tmp/ball.nii" --bench --frames 4 --size 128,128 >"$tmp/bench.txt" || fail "--bench"
grep -q "fps" "$tmp/bench.txt" || fail "--bench prints no frame rate"
echo "view: ok"

#!/bin/sh
# progress.sh — the progress line and Ctrl-C. Under a pseudo-terminal
# (python3's pty) `bvox morph` draws the self-updating line on stderr
# ("\r\033[Kbvox: dilate  42%") and erases it at the end; with stderr a pipe,
# with --json or with --quiet it draws nothing. Ctrl-C (SIGINT) during the
# work ends the command with 130 and leaves no output (a turntable's frames
# written so far are removed).
# BVOX_PROGRESS_DELAY=0 shows the line at once (the default waits 1 s).
# Usage: sh progress.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }
export BVOX_PROGRESS_DELAY=0

"$BVOX" shape sphere r=50 --dims 120,300,120 -o "$tmp/ball.nii" >/dev/null

# run_pty OUTFILE ARGS...: run bvox with stdin, stdout and stderr on a pty,
# the terminal's text to OUTFILE, and exit with its exit status
run_pty() {
    python3 - "$BVOX" "$@" <<'PY'
import os, pty, sys
bvox, out, args = sys.argv[1], sys.argv[2], sys.argv[3:]
pid, fd = pty.fork()
if pid == 0:
    os.execv(bvox, [bvox] + args)
text = b""
while True:
    try:
        d = os.read(fd, 65536)
    except OSError:
        break
    if not d:
        break
    text += d
_, st = os.waitpid(pid, 0)
open(out, "wb").write(text)
sys.exit(os.waitstatus_to_exitcode(st))
PY
}

# on a terminal: the line, updated in place, erased when each call ends
run_pty "$tmp/tty.txt" morph "$tmp/ball.nii" dilate --radius 3 -o "$tmp/d.nii" ||
    fail "morph on a pty failed"
python3 - "$tmp/tty.txt" <<'PY' || fail "no progress line on the terminal"
import re, sys
t = open(sys.argv[1], "rb").read().decode()
pct = [(s, int(p)) for s, p in re.findall(r"\r\x1b\[Kbvox: (\w+) +(\d+)%", t)]
assert pct, repr(t)
stages = [s for s, _ in pct]
assert "dilate" in stages and "write" in stages, stages
d = [p for s, p in pct if s == "dilate"]
assert d == sorted(d) and all(0 <= p < 100 for p in d), d
assert t.endswith("\r\x1b[K"), repr(t[-40:])  # erased at the end
assert "\n" not in t.replace("\r\n", ""), repr(t)  # one line, rewritten
PY
[ -s "$tmp/d.nii" ] || fail "no output"

# --json or --quiet on a terminal: no line
"$BVOX" convert "$tmp/ball.nii" "$tmp/b.tif" --json >/dev/null
run_pty "$tmp/json.txt" convert "$tmp/ball.nii" "$tmp/c.tif" --json || fail "convert --json"
grep -q '%' "$tmp/json.txt" && fail "a progress line with --json"
python3 -c 'import json,sys; json.loads(open(sys.argv[1]).read().strip())' "$tmp/json.txt" ||
    fail "--json output on a terminal is not one JSON object"
run_pty "$tmp/quiet.txt" --quiet morph "$tmp/ball.nii" erode -o "$tmp/e.nii" || fail "--quiet"
[ -s "$tmp/quiet.txt" ] && fail "output on the terminal with --quiet: $(cat "$tmp/quiet.txt")"

# stderr a pipe: nothing but what the command says
"$BVOX" morph "$tmp/ball.nii" dilate --radius 3 -o "$tmp/p.nii" 2>"$tmp/pipe.txt" ||
    fail "morph with stderr in a file"
[ -s "$tmp/pipe.txt" ] && fail "stderr not a terminal but got: $(cat "$tmp/pipe.txt")"

# Ctrl-C after the line shows, in a 360-frame turntable (PNG files written one
# by one, seconds of work): exit 130, no frame left, no temporary
mkdir "$tmp/frames"
python3 - "$BVOX" "$tmp" <<'PY' || fail "Ctrl-C"
import os, pty, signal, sys
bvox, tmp = sys.argv[1:]
frames = os.path.join(tmp, "frames")
pid, fd = pty.fork()
if pid == 0:
    os.execv(bvox, [bvox, "render", os.path.join(tmp, "ball.nii"), "--turntable", "360",
                    "-o", os.path.join(frames, "f.png")])
text = b""
while b"turntable" not in text:
    try:
        d = os.read(fd, 4096)
    except OSError:
        break
    if not d:
        break
    text += d
os.kill(pid, signal.SIGINT)
while True:
    try:
        d = os.read(fd, 4096)
    except OSError:
        break
    if not d:
        break
    text += d
_, st = os.waitpid(pid, 0)
rc = os.waitstatus_to_exitcode(st)
assert rc == 130, (rc, text[-300:])
assert b"canceled" in text, text[-300:]
assert os.listdir(frames) == [], "frames left after Ctrl-C: %d" % len(os.listdir(frames))
PY
exit 0

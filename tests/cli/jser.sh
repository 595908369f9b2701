#!/bin/sh
# jser.sh — `bvox reconstruct SERIES.jser --object NAME` (PyReconstruct's
# series, issue 14 item 13): for both layouts, written here by Python, the
# volume without interpolation is PyReconstruct's own rule (sum of the
# closed traces' shoelace areas, negative ones subtracted, after the current
# alignment, times the section thickness); an open trace is one warning; an
# unknown object is an error naming the objects; --object on a non-.jser
# input is refused.
# Usage: sh jser.sh BVOX DATADIR
set -eu
BVOX=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT INT TERM
fail() { echo "FAIL: $*" >&2; exit 1; }

python3 - "$tmp" <<'PY' >"$tmp/expected"
import json, sys
out = sys.argv[1]
T = 0.04  # every section's thickness
def rect(x0, y0, x1, y1):
    return [x0, x1, x1, x0], [y0, y0, y1, y1]
# per section: (alignment "cur" transform, [(object, xs, ys, closed, negative)])
secs = [
    ([1, 0, 0, 0, 1, 0], [("den", *rect(0, 0, 5.12, 3.0), True, False),
                          ("den", *rect(1, 1, 2.5, 2), True, True),
                          ("ax", *rect(0, 0, 40, 40), True, False)]),
    ([1, 0, 0.5, 0, 1, -0.25], [("den", *rect(0, 0, 4.0, 2.0), True, False),
                                ("den", [0, 1, 2], [0, 2, 0], False, False)]),
    ([2, 0, 0, 0, 2, 0], [("den", *rect(0, 0, 1.28, 1.0), True, False)]),
]
def area(xs, ys, t):
    p = [(t[0] * x + t[1] * y + t[2], t[3] * x + t[4] * y + t[5]) for x, y in zip(xs, ys)]
    return abs(sum(p[i][0] * p[i - 1][1] - p[i - 1][0] * p[i][1] for i in range(len(p)))) / 2
vol = 0
for t, traces in secs:
    for name, xs, ys, closed, neg in traces:
        if name == "den" and closed:
            vol += (-1 if neg else 1) * area(xs, ys, t) * T
print(vol)
def section(t, traces, old):
    d = {"thickness": str(T) if old else T, "mag": 0.002,
         "tforms": {"default": [5, 0, 0, 0, 5, 0], "cur": str(t) if old else t},
         "contours": {}}
    for name, xs, ys, closed, neg in traces:
        if old:
            tr = {"x": ", ".join(map(str, xs)), "y": ", ".join(map(str, ys)),
                  "color": "[0, 0, 0]", "closed": str(closed), "negative": str(neg),
                  "hidden": "False"}
        else:
            tr = [xs, ys, [0, 0, 0], closed, neg, False, ["none", "none"], []]
        d["contours"].setdefault(name, []).append(tr)
    return d
series = {"alignment": "cur", "current_section": 1, "src_dir": ""}
json.dump({"sections": [section(t, tr, False) for t, tr in secs], "series": series, "log": ""},
          open(out + "/cur.jser", "w"))
old = {"s.%d" % i: section(t, tr, True) for i, (t, tr) in enumerate(secs)}
old["s.ser"] = series
json.dump(old, open(out + "/old.jser", "w"))
PY

for layout in cur old; do
    "$BVOX" reconstruct "$tmp/$layout.jser" --object den --no-interpolate --z-spacing 0.01 \
        -o "$tmp/$layout.nii" 2>"$tmp/err" || fail "$layout: $(cat "$tmp/err")"
    n=$(grep -c "bvox: warning: .*1 open trace skipped" "$tmp/err") || true
    [ "$n" = 1 ] || fail "$layout: no one-line open-trace warning: $(cat "$tmp/err")"
    "$BVOX" info "$tmp/$layout.nii" --json >"$tmp/i.json"
    python3 - "$tmp/i.json" "$(cat "$tmp/expected")" <<'PY' || fail "$layout: volume"
import json, sys
o = json.load(open(sys.argv[1]))
want = float(sys.argv[2])
# every edge of den lies on the 0.01 um pixel grid (extent 5.12 um / 512):
# exact but for NIfTI's float32 voxel size
assert abs(o["volume"] - want) <= 1e-6 * want, (o["volume"], want)
PY
    "$BVOX" reconstruct "$tmp/$layout.jser" --object den --no-interpolate --z-spacing 0.01 \
        -o "$tmp/q.nii" --quiet 2>"$tmp/err" || fail "$layout --quiet"
    [ ! -s "$tmp/err" ] || fail "--quiet still printed: $(cat "$tmp/err")"
done

if "$BVOX" reconstruct "$tmp/cur.jser" --object spine -o "$tmp/x.nii" 2>"$tmp/err"; then
    fail "an unknown object was accepted"
fi
grep -q "^bvox: .*no closed trace of object 'spine' (objects: den, ax)" "$tmp/err" ||
    fail "unknown object message: $(cat "$tmp/err")"
[ ! -e "$tmp/x.nii" ] || fail "a file was written on error"

printf '{"sections":[{"contours":[[[5,5],[15,5],[15,15],[5,15]]]}]}' >"$tmp/c.json"
if "$BVOX" reconstruct "$tmp/c.json" --object den -o "$tmp/y.nii" 2>"$tmp/err"; then
    fail "--object accepted for a JSON stack"
fi
grep -q "not one" "$tmp/err" || fail "--object on JSON: $(cat "$tmp/err")"
echo "jser: ok"

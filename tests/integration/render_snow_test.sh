#!/usr/bin/env bash
# deepsea render --snow (docs/snow-shadows.md, "Marine snow"): the snow and snow_id layers, the
# manifest's settings.snow, --resume refusing other snow settings, a bad preset refused with one
# line and exit 2 before any work, the setup's snow section.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
"$ds" scene --out "$work/in" --frames 2 --width 160 --height 120 --altitude 1.5 -q
"$ds" bake --camera "$work/in/camera.yaml" --rig "$src/volumes/rigs/authors-testset.yaml" \
  --water jerlov:IB --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
rgb=$work/in/'*.png' depth=$work/in/'*_depth.exr'
render() { "$ds" render --asset "$work/a.vdb" --rgb "$rgb" --depth "$depth" "$@"; }

# 1. A sequence with snow: the layers, and the snow added to final (final - snow is the frame
# without snow, to float rounding); the manifest records preset, seed and focus distance.
render -o "$work/seq" --layers "$work/lay" --snow nepheloid --snow-seed 7 --exposure 100 \
  | grep -q "rendered 2 frame(s)"
render --layers "$work/plain" --exposure 100 | grep -q "rendered 2 frame(s)"
/usr/bin/python3 - "$work/lay" "$work/plain" "$work/seq" <<'PY'
import json, os, sys
import numpy as np
import OpenImageIO as oiio
lay, plain, seq = sys.argv[1:]
def read(path):
    f = oiio.ImageInput.open(path)
    names = list(f.spec().channelnames)
    px = f.read_image("float")
    return {n: px[..., i] for i, n in enumerate(names)}
for name in ("frame_0001.exr", "frame_0002.exr"):
    a, b = read(os.path.join(lay, name)), read(os.path.join(plain, name))
    for ch in ("snow.R", "snow.G", "snow.B", "snow_id.id"):
        assert ch in a, (name, sorted(a))
        assert ch not in b, (name, ch)
    assert a["snow.G"].sum() > 0, "no snow drawn"
    ids = a["snow_id.id"]
    assert (ids == np.round(ids)).all() and ids.max() >= 1, "ids"
    # where no particle adds light there is no id, and the reverse
    lit = (a["snow.R"] + a["snow.G"] + a["snow.B"]) > 0
    assert ((ids > 0) == lit).all(), "ids where snow is"
    for c in "RGB":
        diff = a["final." + c] - a["snow." + c] - b["final." + c]
        assert np.abs(diff).max() <= 1e-5 * max(1.0, np.abs(b["final." + c]).max()), c
for folder in (lay, seq):
    m = json.load(open(os.path.join(folder, "deepsea-sequence.json")))
    s = m["settings"]["snow"]
    assert s["preset"] == "nepheloid" and s["seed"] == 7 and s["focus_distance_m"] > 0, s
m = json.load(open(os.path.join(plain, "deepsea-sequence.json")))
assert "snow" not in m.get("settings", {}), m
PY

# 2. --resume with other snow settings: refused, one line, nothing rewritten.
sum_before=$(cat "$work"/lay/* "$work"/seq/* | md5sum)
expect_fail "resume with another preset" render -o "$work/seq" --layers "$work/lay" --resume \
  --snow plume --snow-seed 7 --exposure 100
grep -q "snow" "$work/err.txt"
grep -q -- "--snow" "$work/err.txt"
expect_fail "resume with another seed" render -o "$work/seq" --layers "$work/lay" --resume \
  --snow nepheloid --snow-seed 8 --exposure 100
grep -q -- "--snow-seed" "$work/err.txt"
expect_fail "resume without snow" render -o "$work/seq" --layers "$work/lay" --resume \
  --exposure 100
[[ $(cat "$work"/lay/* "$work"/seq/* | md5sum) == "$sum_before" ]] || { echo "FAIL: layers changed"; exit 1; }
render -o "$work/seq" --layers "$work/lay" --resume --snow nepheloid --snow-seed 7 --exposure 100 \
  | grep -q "skipped 2"

# 3. An unknown preset: one line naming it, exit 2, nothing written.
expect_fail "unknown preset" render -o "$work/bad" --snow blizzard
[[ $(grep -c "blizzard" "$work/err.txt") -eq 1 ]]
set +e; render -o "$work/bad" --snow blizzard 2>/dev/null; rc=$?; set -e
[[ $rc -eq 2 ]] || { echo "FAIL: unknown preset exit $rc, not 2"; exit 1; }
expect_absent "$work/bad"

# 4. A snow section in the --camera file (docs/config.md): applies without --snow, its values
# recorded in the manifest; --snow overrides it; a value out of range names its key and line.
{ cat "$work/in/camera.yaml"; printf 'snow:\n  preset: plume\n  albedo: 0.3\n'; } > "$work/cam_snow.yaml"
render --camera "$work/cam_snow.yaml" --layers "$work/yaml" --exposure 100 | grep -q "rendered 2"
render --camera "$work/cam_snow.yaml" --layers "$work/yaml_off" --exposure 100 --snow off \
  | grep -q "rendered 2"
/usr/bin/python3 - "$work/yaml" "$work/yaml_off" <<'PY'
import json, os, sys
import OpenImageIO as oiio
on, off = sys.argv[1:]
s = json.load(open(os.path.join(on, "deepsea-sequence.json")))["settings"]["snow"]
assert s["preset"] == "custom" and s["albedo"] == 0.3 and s["concentration"] == 5000, s
assert "snow" not in json.load(open(os.path.join(off, "deepsea-sequence.json")))["settings"]
assert "snow.R" in oiio.ImageInput.open(os.path.join(on, "frame_0001.exr")).spec().channelnames
assert "snow.R" not in oiio.ImageInput.open(os.path.join(off, "frame_0001.exr")).spec().channelnames
PY
{ cat "$work/in/camera.yaml"; printf 'snow:\n  preset: plume\n  albedo: 1.5\n'; } > "$work/cam_bad.yaml"
expect_fail "albedo out of range" render --camera "$work/cam_bad.yaml" -o "$work/bad"
line=$(( $(wc -l < "$work/in/camera.yaml") + 3 ))
grep -q "cam_bad.yaml:$line: snow.albedo: must be in (0, 1\]" "$work/err.txt"
expect_absent "$work/bad"

# 5. --poses (TUM): the n-th pose is the n-th frame's; snow then fixed in the world (other
# particles than without poses); a wrong count or a bad line is refused naming file (and line).
printf '# timestamp tx ty tz qx qy qz qw\n1.0 0 0 0 0 0 0 1\n2.0 0.25 0 0 0 0 0 1\n' > "$work/poses.txt"
render --layers "$work/posed" --snow plume --poses "$work/poses.txt" --exposure 100 \
  | grep -q "rendered 2"
render --layers "$work/unposed" --snow plume --exposure 100 | grep -q "rendered 2"
/usr/bin/python3 - "$work/posed/frame_0001.exr" "$work/unposed/frame_0001.exr" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
a, b = (oiio.ImageInput.open(f).read_image("float") for f in sys.argv[1:])
assert not np.array_equal(a, b), "poses changed nothing"
PY
head -2 "$work/poses.txt" > "$work/one_pose.txt"
expect_fail "one pose for two frames" render -o "$work/bad" --snow plume --poses "$work/one_pose.txt"
grep -q "one_pose.txt: 1 pose(s) for 2 frame(s)" "$work/err.txt"
printf '1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n' > "$work/short.txt"
expect_fail "a short line" render -o "$work/bad" --snow plume --poses "$work/short.txt"
grep -q "short.txt:2: expected 8 numbers" "$work/err.txt"
expect_absent "$work/bad"
# the manifest records the poses: --resume with other poses is refused in one line, with the
# same ones it goes on
grep -q '"poses"' "$work/posed/deepsea-sequence.json"
render --layers "$work/posed" --snow plume --poses "$work/poses.txt" --exposure 100 --resume \
  | grep -q "skipped 2"
printf '1.0 0 0 0 0 0 0 1\n2.0 0.5 0 0 0 0 0 1\n' > "$work/other.txt"
expect_fail "other poses" render --layers "$work/posed" --snow plume --poses "$work/other.txt" \
  --exposure 100 --resume
grep -q "cannot resume: --poses was 2 pose(s)" "$work/err.txt"
test "$(wc -l < "$work/err.txt")" -eq 1
expect_fail "no poses" render --layers "$work/posed" --snow plume --exposure 100 --resume
grep -q "cannot resume: --poses was 2 pose(s) .*, now not given" "$work/err.txt"

# 6. Frames named by their timestamps (TUM RGB-D): each takes the pose at its time from a
# trajectory with more poses than frames; a frame beyond 0.02 s of every pose is refused in one
# line naming the frame and the poses file, nothing written. With --snow-streaks the snow is
# drawn as motion streaks (recorded in the manifest); without snow the flag is refused.
mkdir -p "$work/tum"
cp "$work/in/frame_0001.png" "$work/tum/1305031102.175304.png"
cp "$work/in/frame_0001_depth.exr" "$work/tum/1305031102.175304_depth.exr"
cp "$work/in/frame_0002.png" "$work/tum/1305031102.208637.png"
cp "$work/in/frame_0002_depth.exr" "$work/tum/1305031102.208637_depth.exr"
tum() { "$ds" render --asset "$work/a.vdb" --rgb "$work/tum/*.png" --depth "$work/tum/*_depth.exr" "$@"; }
for t in 17 18 19 20 21 22; do echo "1305031102.$t 0.$t 0 0 0 0 0 1"; done > "$work/gt.txt"
tum --layers "$work/tum_still" --snow plume --poses "$work/gt.txt" --exposure 100 | grep -q "rendered 2"
tum --layers "$work/tum_streaks" --snow plume --snow-streaks --poses "$work/gt.txt" --exposure 100 \
  | grep -q "rendered 2"
/usr/bin/python3 - "$work/tum_still" "$work/tum_streaks" <<'PY'
import json, os, sys
import numpy as np
import OpenImageIO as oiio
still, streaks = sys.argv[1:]
name = "1305031102.208637.exr"
a, b = (oiio.ImageInput.open(os.path.join(f, name)).read_image("float") for f in (still, streaks))
assert not np.array_equal(a, b), "streaks changed nothing"
s = json.load(open(os.path.join(streaks, "deepsea-sequence.json")))["settings"]["snow"]
assert s["streaks"] == 1 and s["streak_exposure_ms"] == 10, s
s = json.load(open(os.path.join(still, "deepsea-sequence.json")))["settings"]["snow"]
assert s["streaks"] == 0, s
PY
head -2 "$work/gt.txt" > "$work/gt_short.txt"
expect_fail "a frame past the trajectory" tum -o "$work/bad" --snow plume --poses "$work/gt_short.txt"
grep -q "gt_short.txt: no pose within 0.020000 s of frame .*1305031102.208637.png" "$work/err.txt"
test "$(wc -l < "$work/err.txt")" -eq 1
expect_absent "$work/bad"
expect_fail "streaks without snow" render -o "$work/bad" --snow-streaks
grep -q -- "--snow-streaks" "$work/err.txt"
expect_absent "$work/bad"
echo "render --snow: ok"

#!/usr/bin/env bash
# deepsea render --snow (docs/model.md, "Marine snow"): the snow and snow_id layers, the
# manifest's settings.snow, --resume refusing other snow settings, a bad preset refused with one
# line and exit 2 before any work.
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
sum_before=$(cat "$work"/lay/* | md5sum)
expect_fail "resume with another preset" render --layers "$work/lay" --resume --snow plume \
  --snow-seed 7 --exposure 100
grep -q "snow" "$work/err.txt"
expect_fail "resume with another seed" render --layers "$work/lay" --resume --snow nepheloid \
  --snow-seed 8 --exposure 100
expect_fail "resume without snow" render --layers "$work/lay" --resume --exposure 100
[[ $(cat "$work"/lay/* | md5sum) == "$sum_before" ]] || { echo "FAIL: layers changed"; exit 1; }
render --layers "$work/lay" --resume --snow nepheloid --snow-seed 7 --exposure 100 \
  | grep -q "skipped 2"

# 3. An unknown preset: one line naming it, exit 2, nothing written.
expect_fail "unknown preset" render -o "$work/bad" --snow blizzard
[[ $(grep -c "blizzard" "$work/err.txt") -eq 1 ]]
set +e; render -o "$work/bad" --snow blizzard 2>/dev/null; rc=$?; set -e
[[ $rc -eq 2 ]] || { echo "FAIL: unknown preset exit $rc, not 2"; exit 1; }
expect_absent "$work/bad"
echo "render --snow: ok"

#!/usr/bin/env bash
# deepsea render from the command line: one frame, a sequence with --resume, depth sentinels,
# and bad input: one line on stderr, a non-zero exit, no output file left behind.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
v=$src/volumes
cam=$v/cameras/small-320.yaml

"$ds" scene --out "$work/in" --frames 3 --camera "$cam" >/dev/null
"$ds" bake --camera "$cam" --rig "$v/rigs/authors-testset.yaml" --water jerlov:IB \
  -o "$work/a.vdb" >/dev/null
f1=$work/in/frame_0001.png d1=$work/in/frame_0001_depth.exr

"$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" -o "$work/one.png" \
  --layers "$work/one.exr" | grep -q "wrote $work/one.png"
[[ -s $work/one.png && -s $work/one.exr ]]

"$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  -o "$work/seq" | grep -q "rendered 3 frame(s), skipped 0, failed 0"
"$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  -o "$work/seq" --resume | grep -q "rendered 0 frame(s), skipped 3, failed 0"

# A depth map full of sentinels and absurd values (1e10, 1e29, NaN, inf, -1) renders, quickly.
/usr/bin/python3 - "$d1" "$work/odd_depth.exr" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
src = oiio.ImageInput.open(sys.argv[1])
d = src.read_image("float")
src.close()
d[:, 0::5] = 1e10
d[:, 1::5] = 1e29
d[0::4, 2::5] = np.nan
d[1::4, 2::5] = np.inf
d[2::4, 2::5] = -1.0
out = oiio.ImageOutput.create(sys.argv[2])
out.open(sys.argv[2], oiio.ImageSpec(d.shape[1], d.shape[0], 1, "float"))
out.write_image(d)
out.close()
PY
timeout 60 "$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$work/odd_depth.exr" \
  -o "$work/odd.png" | grep -q "wrote $work/odd.png"

source "$(dirname "$0")/cli_lib.sh"
/usr/bin/python3 -c "
import OpenImageIO as oiio, numpy as np
o = oiio.ImageOutput.create('$work/small_depth.exr')
o.open('$work/small_depth.exr', oiio.ImageSpec(160, 120, 1, 'float'))
o.write_image(np.full((120, 160, 1), 3.0, np.float32))
o.close()"
expect_fail "sizes differ" \
  "$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$work/small_depth.exr" -o "$work/bad1.png"
expect_fail "missing depth" \
  "$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$work/none.exr" -o "$work/bad2.png"
head -c 3000 "$f1" > "$work/cut.png"
expect_fail "truncated colour" \
  "$ds" render --asset "$work/a.vdb" --rgb "$work/cut.png" --depth "$d1" -o "$work/bad3.png"
expect_fail "empty glob" \
  "$ds" render --asset "$work/a.vdb" --rgb "$work/nothing/*.png" --depth "$work/in/*_depth.exr" \
  -o "$work/bad4"
"$ds" bake --camera "$v/cameras/authors-800.yaml" --rig "$v/rigs/single-down.yaml" \
  --water jerlov:IB --xy-step 64 --depth-samples 4 -o "$work/other.vdb" >/dev/null
expect_fail "asset of another camera" \
  "$ds" render --asset "$work/other.vdb" --rgb "$f1" --depth "$d1" -o "$work/bad5.png"
expect_fail "unwritable output" \
  "$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" -o /nonexistent/x.png
expect_absent "$work"/bad[1235].png "$work/bad4" /nonexistent/x.png

# --layer-set and --half: only the chosen layers, in half floats, the same values as the full
# float file's to half precision; a sequence's manifest records both; an unknown layer is a
# usage error (exit 2, one line) before any work.
"$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" --layers "$work/some.exr" \
  --layer-set depth,final --half | grep -q "wrote $work/some.exr"
"$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  --layers "$work/lay" --layer-set backscatter --half | grep -q "rendered 3 frame(s)"
/usr/bin/python3 - "$work/one.exr" "$work/some.exr" "$work/lay" <<'PY'
import json, os, sys
import numpy as np
import OpenImageIO as oiio
full, some, lay = sys.argv[1:]
a, b = oiio.ImageInput.open(full), oiio.ImageInput.open(some)
assert a.spec().nchannels == 19 and a.spec().format == "float", a.spec().channelnames
assert sorted(b.spec().channelnames) == ["depth.Z", "final.B", "final.G", "final.R"], \
    b.spec().channelnames
assert b.spec().format == "half", b.spec().format
fa, fb = a.read_image("float"), b.read_image("float")
for i, name in enumerate(b.spec().channelnames):
    ref = fa[..., list(a.spec().channelnames).index(name)]
    assert np.allclose(fb[..., i], ref, rtol=1e-3, atol=1e-6), name
assert b.spec().getattribute("deepsea:exposure"), "metadata"
m = json.load(open(os.path.join(lay, "deepsea-sequence.json")))
assert m["outputs"]["layers"] == "backscatter" and m["outputs"]["half"] is True, m["outputs"]
names = [f for f in os.listdir(lay) if f.endswith(".exr")]
assert len(names) == 3, names
assert sorted(oiio.ImageInput.open(os.path.join(lay, names[0])).spec().channelnames) == \
    ["backscatter.B", "backscatter.G", "backscatter.R"]
PY
# --resume with another layer set or without --half is refused.
expect_fail "resume with another layer set" \
  "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  --layers "$work/lay" --layer-set final --half --resume
grep -q -- "--layer-set" "$work/err.txt"
"$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  --layers "$work/lay" --layer-set backscatter --half --resume | grep -q "skipped 3"
for bad in "final,bogus" "final,final" ""; do
  set +e
  "$ds" render --asset "$work/a.vdb" --rgb "$f1" --depth "$d1" --layers "$work/bad6.exr" \
    --layer-set "$bad" >"$work/out.txt" 2>"$work/err.txt"
  rc=$?
  set -e
  [[ $rc -eq 2 && $(wc -l <"$work/err.txt") -eq 1 ]] || { echo "FAIL --layer-set '$bad': exit $rc"; cat "$work/err.txt"; exit 1; }
  echo "ok --layer-set '$bad' (exit 2): $(cat "$work/err.txt")"
done
grep -q "unknown layer\|no layer\|twice\|an empty value" "$work/err.txt"
expect_absent "$work/bad6.exr"
echo "render CLI: OK"

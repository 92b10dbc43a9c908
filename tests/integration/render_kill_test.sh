#!/usr/bin/env bash
# Kills during `deepsea render` of a sequence (issue 10, part 7): SIGINT and SIGTERM stop it
# after the frames in flight, leaving complete outputs and no temporaries; SIGKILL may leave
# hidden temporaries but never a partial file under a frame's name. In every case the same
# command with --resume finishes the job byte for byte as an uninterrupted run.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
cam=$src/volumes/cameras/small-320.yaml
n=10
"$ds" scene --out "$work/in" --frames $n --camera "$cam" >/dev/null
"$ds" bake --camera "$cam" --rig "$src/volumes/rigs/authors-testset.yaml" --water jerlov:IB \
  --xy-step 16 --depth-samples 16 -o "$work/a.vdb" >/dev/null
# exec: in the background, $! is then deepsea itself, not a subshell.
render() {
  exec "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
    -o "$work/$1/img" --layers "$work/$1/layers" "${@:2}"
}
(render ref >/dev/null)

# Every visible output decodes fully; prints how many there are.
check_complete() {
  /usr/bin/python3 - "$@" <<'PY'
import sys
import OpenImageIO as oiio
n = 0
for f in sys.argv[1:]:
    inp = oiio.ImageInput.open(f)
    assert inp is not None, f + ": " + oiio.geterror()
    px = inp.read_image("float")
    assert px is not None and px.size > 0, f + ": cannot decode: " + inp.geterror()
    inp.close()
    n += 1
print(n)
PY
}

for sig in INT TERM KILL; do
  out=$work/$sig
  set +e
  (render "$sig" >"$work/$sig.out" 2>"$work/$sig.err") &
  pid=$!
  set -e
  # Kill once the first layer file is there: later frames are being composited or written.
  for _ in $(seq 600); do
    compgen -G "$out/layers/frame_*.exr" >/dev/null && break
    sleep 0.05
  done
  kill -"$sig" "$pid"
  set +e; wait "$pid"; rc=$?; set -e
  visible=$(find "$out" -name 'frame_*' ! -name '.*' | sort)
  done_frames=$(check_complete $visible)
  hidden=$(find "$out" -name '.*' | wc -l)
  echo "SIG$sig: exit $rc, $done_frames complete outputs, $hidden hidden file(s)"
  if [[ $rc -eq 0 ]]; then echo "FAIL SIG$sig: the render finished before the signal"; exit 1; fi
  if [[ $(find "$out/img" -name 'frame_*.png' | wc -l) -ge $n ]]; then
    echo "FAIL SIG$sig: not interrupted mid-way"; exit 1
  fi
  if [[ $sig != KILL ]]; then
    [[ $rc -eq 130 ]] || { echo "FAIL SIG$sig: exit $rc, expected 130"; cat "$work/$sig.err"; exit 1; }
    [[ $(wc -l <"$work/$sig.err") -eq 1 ]] && grep -q "stopped by signal" "$work/$sig.err" \
      || { echo "FAIL SIG$sig: stderr:"; cat "$work/$sig.err"; exit 1; }
    [[ $hidden -eq 0 ]] || { echo "FAIL SIG$sig: hidden files left:"; find "$out" -name '.*'; exit 1; }
  fi
  # Each folder's manifest is whole (written to a temporary and renamed) and never counts a
  # frame whose outputs are not all there (the manifests are written from a thread of their
  # own as frames finish); after INT or TERM its last write counts every frame written.
  /usr/bin/python3 - "$out" "$sig" <<'PY'
import json, os, sys
out, sig = sys.argv[1:]
stems = lambda d, ext: {f[:-len(ext)] for f in os.listdir(d) if f.startswith("frame_") and f.endswith(ext)}
both = len(stems(out + "/img", ".png") & stems(out + "/layers", ".exr"))
for d in ("img", "layers"):
    m = json.load(open(os.path.join(out, d, "deepsea-sequence.json")))
    done = m["frames"]["done"]
    assert m["frames"]["total"] == 10 and m["exposure"]["factor"] > 0, (d, m)
    assert done <= both, f"SIG{sig}: {d}/deepsea-sequence.json counts {done} frames, {both} complete"
    assert sig == "KILL" or done == both, f"SIG{sig}: {d}: done {done}, {both} frames written"
PY
  (render "$sig" --resume >"$work/$sig.resume")
  grep -q "failed 0" "$work/$sig.resume"
  cat "$work/$sig.resume"
  [[ -z $(find "$out" -name '.*') ]] || { echo "FAIL SIG$sig: hidden files after --resume"; exit 1; }
  # PNGs byte for byte; layer EXRs pixel for pixel and metadata (OpenEXR stamps DateTime).
  for f in "$work"/ref/img/*.png; do cmp "$f" "$out/img/$(basename "$f")"; done
  /usr/bin/python3 - "$work/ref/layers" "$out/layers" <<'PY'
import os, sys
import numpy as np
import OpenImageIO as oiio
ref, out = sys.argv[1:]
names = sorted(f for f in os.listdir(ref) if f.endswith(".exr"))
assert names == sorted(f for f in os.listdir(out) if f.endswith(".exr")), "layer files differ"
for name in names:
    a, b = oiio.ImageInput.open(os.path.join(ref, name)), oiio.ImageInput.open(os.path.join(out, name))
    assert list(a.spec().channelnames) == list(b.spec().channelnames), name
    assert np.array_equal(a.read_image("float"), b.read_image("float")), name + ": pixels differ"
    for key in ("deepsea:exposure", "deepsea:asset_hash"):
        assert a.spec().getattribute(key) == b.spec().getattribute(key), name + ": " + key
PY
  cmp <(grep -v chosen_on "$work/ref/img/deepsea-sequence.json") \
    <(grep -v chosen_on "$out/img/deepsea-sequence.json")
done
echo "render kills: OK"

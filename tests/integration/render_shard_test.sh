#!/usr/bin/env bash
# deepsea render --shard (docs/sequences.md, "Shards"): four shards, run at once into the same
# folders, then `deepsea merge-shards`, give the same bytes as one unsharded render: every
# image and the manifest (auto exposure, a fixed one, a camera stage without its controller);
# an array job's variables with --shard array; a shard resumes alone; the merge refuses missing,
# unfinished or disagreeing shards, and a shard refuses what would make it differ.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"
cat >"$work/cam.yaml" <<'YAML'
camera: {width: 64, height: 48, fx: 48.0, fy: 48.0, cx: 31.5, cy: 23.5}
YAML
"$ds" scene --out "$work/in" --frames 10 --camera "$work/cam.yaml" >/dev/null
rm "$work/in/camera.yaml"
"$ds" bake --camera "$work/cam.yaml" --rig "$src/volumes/rigs/authors-testset.yaml" \
  --water jerlov:IB --xy-step 8 --depth-samples 8 -o "$work/a.vdb" >/dev/null
render() { "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" "$@"; }
# same A B: the same file names in both folders (hidden ones too) and the same bytes.
same() {
  [[ $(cd "$1" && ls -A) == $(cd "$2" && ls -A) ]] || { echo "FAIL: $1 and $2 hold other files"; ls -A "$1" "$2"; exit 1; }
  local f
  for f in "$1"/*; do cmp "$f" "$2/$(basename "$f")"; done
}
# shards OUT N ARGS...: shards 0..N-1 at once into OUT (-o), then the merge.
shards() {
  local out=$1 n=$2 i pids=(); shift 2
  for ((i = 0; i < n; i++)); do
    render -o "$out" --shard "$i/$n" "$@" >"$work/shard$i.txt" & pids+=($!)
  done
  for i in "${pids[@]}"; do wait "$i"; done
  for ((i = 0; i < n; i++)); do grep -q "^shard $i/$n: rendered " "$work/shard$i.txt"; done
  "$ds" merge-shards "$out" | grep -q "$n shard(s), 10 frame(s): wrote"
}

# 1. Auto exposure: every shard chooses it on the sequence's first frame; 4 shards = 1 run.
render -o "$work/full" --layers "$work/full_lay" >/dev/null
render -o "$work/full_o" >/dev/null
shards "$work/s4" 4 --layers "$work/s4_lay"
same "$work/full" "$work/s4"
"$ds" merge-shards "$work/s4_lay" >/dev/null
cmp "$work/full_lay/deepsea-sequence.json" "$work/s4_lay/deepsea-sequence.json"
/usr/bin/python3 - "$work/full_lay" "$work/s4_lay" <<'PY'
import sys, os
import OpenImageIO as oiio
a, b = sys.argv[1:3]
for f in sorted(os.listdir(a)):
    if f.endswith(".exr"):  # EXR headers carry the time they were written: pixels, not bytes
        x, y = oiio.ImageBuf(f"{a}/{f}"), oiio.ImageBuf(f"{b}/{f}")
        assert (x.get_pixels(oiio.FLOAT) == y.get_pixels(oiio.FLOAT)).all(), f
PY
echo "ok 4 shards (auto exposure) = one render, byte for byte"

# 2. A fixed exposure, 3 uneven shards (4, 3, 3 frames), JPEG.
render -o "$work/full_fix" --exposure 80 --format jpg >/dev/null
shards "$work/s3" 3 --exposure 80 --format jpg
same "$work/full_fix" "$work/s3"
echo "ok 3 shards (fixed exposure, JPEG) = one render"

# 3. A camera stage without its controller: noise keyed per frame, so shards are exact.
cat >"$work/stage.yaml" <<'YAML'
camera:
  {width: 64, height: 48, fx: 48.0, fy: 48.0, cx: 31.5, cy: 23.5,
   sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 25}}
YAML
render -o "$work/full_cam" --camera "$work/stage.yaml" >/dev/null
shards "$work/s_cam" 4 --camera "$work/stage.yaml"
same "$work/full_cam" "$work/s_cam"
echo "ok 4 shards with a camera stage = one render"

# 4. Array jobs: Slurm (task ids 1..2) and Kubernetes indexed Jobs, with --shard array only.
for t in 1 2; do
  SLURM_ARRAY_TASK_ID=$t SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=2 \
    render -o "$work/slurm" --shard array | grep -q "^shard $((t - 1))/2: rendered 5 frame(s)"
done
"$ds" merge-shards "$work/slurm" >/dev/null
same "$work/full_o" "$work/slurm"
for t in 0 1 2; do
  JOB_COMPLETION_INDEX=$t render -o "$work/k8s" --shard array --shard-count 3 >/dev/null
done
"$ds" merge-shards "$work/k8s" >/dev/null
same "$work/full_o" "$work/k8s"
# Without --shard an array job's variables change nothing: a render is never split unasked.
SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=4 render -o "$work/whole" \
  | grep -q "^rendered 10 frame(s)"
same "$work/full_o" "$work/whole"
echo "ok --shard array (Slurm, Kubernetes); none without it"

# 5. The merge refuses missing, unfinished and disagreeing shards; a shard resumes alone.
for i in 0 1 2; do render -o "$work/part" --shard "$i/4" >/dev/null; done
expect_fail "a shard missing" "$ds" merge-shards "$work/part"
grep -q "shard(s) 3 of 4 have no manifest here" "$work/err.txt"
rc=$(set +e; "$ds" merge-shards "$work/part" >/dev/null 2>&1; echo $?); [[ $rc -eq 6 ]] || { echo "FAIL: exit $rc, want 6"; exit 1; }
render -o "$work/part" --shard 3/4 --exposure 80 >/dev/null
expect_fail "shards disagree" "$ds" merge-shards "$work/part"
grep -q "shards 0 and 3 differ in exposure" "$work/err.txt"
render -o "$work/part" --shard 3/4 >/dev/null
rm "$work/part/frame_0005.png"  # shard 1's second frame
expect_fail "an output missing" "$ds" merge-shards "$work/part" --check
grep -q "1 output(s) missing.*frame_0005.png" "$work/err.txt"
expect_fail "a shard resumes only with its own settings" \
  render -o "$work/part" --shard 1/4 --resume --bits 16
grep -q "cannot resume: --bits was 8, now 16" "$work/err.txt"
render -o "$work/part" --shard 1/4 --resume | grep -q "^shard 1/4: rendered 1 frame(s), skipped 2"
"$ds" merge-shards "$work/part" --check | grep -q "4 shard(s) agree, all 10 frame(s) there"
"$ds" merge-shards "$work/part" >/dev/null
same "$work/full_o" "$work/part"
expect_fail "merged already" "$ds" merge-shards "$work/part"
grep -q "merged already" "$work/err.txt"
# An unsharded --resume continues a merged folder.
rm "$work/part/frame_0010.png"
render -o "$work/part" --resume | grep -q "^rendered 1 frame(s), skipped 9"
same "$work/full_o" "$work/part"
echo "ok merge refusals; a shard resumes alone; a merged folder resumes"

# 6. Shards and unsharded runs exclude each other (shared lock, here held by flock(1)).
mkdir "$work/busy"
flock -s "$work/busy/.deepsea.lock" sleep 30 &
holder=$!
for _ in $(seq 50); do [[ -e $work/busy/.deepsea.lock ]] && break; sleep 0.1; done
render -o "$work/busy" --shard 0/2 >/dev/null   # another shard may hold it too
expect_fail "unsharded render while shards run" render -o "$work/busy"
expect_fail "merge while shards run" "$ds" merge-shards "$work/busy"
grep -q "another deepsea process" "$work/err.txt"
kill "$holder"; wait "$holder" 2>/dev/null || true

# 7. What a shard refuses, before any work (exit 2).
bad_shard() {
  local name=$1; shift
  expect_fail "$name" "$@"
  rc=$(set +e; "$@" >/dev/null 2>&1; echo $?); [[ $rc -eq 2 ]] || { echo "FAIL $name: exit $rc"; exit 1; }
}
cat >"$work/ae.yaml" <<'YAML'
camera:
  {width: 64, height: 48, fx: 48.0, fy: 48.0, cx: 31.5, cy: 23.5,
   sensor: {preset: mvbluefox3-2051c, exposure_time_ms: 0.5}, auto_exposure: {target: 0.4}}
YAML
bad_shard "controller" render -o "$work/no1" --shard 0/2 --camera "$work/ae.yaml"
grep -q "auto_exposure controller sets each frame's exposure from the frames before it" "$work/err.txt"
bad_shard "more shards than frames" render -o "$work/no2" --shard 0/11
bad_shard "one frame" "$ds" render --asset "$work/a.vdb" --rgb "$work/in/frame_0001.png" \
  --depth "$work/in/frame_0001_depth.exr" -o "$work/no3.png" --shard 0/2
bad_shard "i >= n" render -o "$work/no4" --shard 2/2
bad_shard "not i/n" render -o "$work/no5" --shard 2
bad_shard "array outside an array job" env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX \
  "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
  -o "$work/no6" --shard array
expect_absent "$work/no1" "$work/no2" "$work/no3.png" "$work/no4" "$work/no5" "$work/no6"
echo "render shards: OK"

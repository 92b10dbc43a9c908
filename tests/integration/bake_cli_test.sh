#!/usr/bin/env bash
# deepsea bake / info / bake-library from the command line: a small bake, info as text and
# JSON, a sharded library that a second run skips, and bad input: one line, non-zero exit, no
# .vdb left behind.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
v=$src/volumes
small=(--camera "$v/cameras/small-320.yaml" --rig "$v/rigs/authors-testset.yaml" --water jerlov:IB
       --xy-step 32 --depth-samples 8)

"$ds" bake "${small[@]}" -o "$work/a.vdb" | grep -q "wrote $work/a.vdb"
"$ds" info "$work/a.vdb" | grep -q "camera     320x240"
"$ds" info "$work/a.vdb" --json | /usr/bin/python3 -c \
  'import json,sys; j=json.load(sys.stdin); assert j["bake"]["camera"]["width"]==320, j'

# bad input: exit code, exactly one line on stderr, no output file
source "$(dirname "$0")/cli_lib.sh"

# the bake's own check: recorded, shown by info (text and JSON); an explicit step wins; a coarse
# lattice that misses the bar is a loud warning, and an error with --strict-check (exit 7, no
# file); --no-check records none
"$ds" info "$work/a.vdb" | grep -q "^lattice    .* step 32 px; 9 depth samples (log)"
"$ds" info "$work/a.vdb" | grep -Eq "^check      mean [0-9.]+ %, max [0-9.]+ % at pixel"
"$ds" info "$work/a.vdb" --json | /usr/bin/python3 -c \
  'import json,sys; c=json.load(sys.stdin)["bake"]["check"]; assert c["pixels"]>0 and c["max_rel"]>=c["mean_rel"]>0, c'
"$ds" bake "${small[@]}" --xy-step 160 -o "$work/coarse.vdb" 2>"$work/warn.txt" >/dev/null
grep -q "^warning: .*MISSES the bar" "$work/warn.txt"
"$ds" info "$work/coarse.vdb" | grep -q "step 160 px;"
expect_fail "strict check misses the bar" "$ds" bake "${small[@]}" --xy-step 160 --strict-check \
  -o "$work/bad-strict.vdb"
grep -q "misses the bar" "$work/err.txt"
set +e; "$ds" bake "${small[@]}" --xy-step 160 --strict-check -o "$work/bad-strict.vdb" 2>/dev/null
rc=$?; set -e
[[ $rc -eq 7 ]] || { echo "FAIL strict check: exit $rc, expected 7"; exit 1; }
"$ds" bake "${small[@]}" --no-check -o "$work/nocheck.vdb" >/dev/null
"$ds" info "$work/nocheck.vdb" | grep -q "^check      not checked"
expect_fail "K < 2" "$ds" bake "${small[@]}" --depth-samples 1 -o "$work/bad1.vdb"
expect_fail "z_max <= 0" "$ds" bake "${small[@]}" --z-max -1 -o "$work/bad2.vdb"
expect_fail "unknown preset" "$ds" bake --camera "$v/cameras/small-320.yaml" \
  --rig "$v/rigs/authors-testset.yaml" --water jerlov:XX -o "$work/bad3.vdb"
expect_fail "missing folder" "$ds" bake "${small[@]}" -o "$work/no/such/dir/x.vdb"
head -c 2000 "$work/a.vdb" > "$work/truncated.vdb"
expect_fail "truncated asset" "$ds" info "$work/truncated.vdb"
echo "not a vdb" > "$work/text.vdb"
expect_fail "foreign file" "$ds" info "$work/text.vdb"
expect_fail "missing asset" "$ds" info "$work/none.vdb"
ls "$work"/bad*.vdb 2>/dev/null && { echo "FAIL: partial output left"; exit 1; }
ls -a "$work" | grep -q tmp && { echo "FAIL: temporary file left"; exit 1; }

# a library in two shards: disjoint, complete, and a second run skips everything
cat > "$work/lib.yaml" <<YAML
cameras: [$v/cameras/small-320.yaml]
rigs: [$v/rigs/authors-testset.yaml, $v/rigs/single-down.yaml]
waters: [jerlov:IB, $v/waters/jerlov-3C.yaml]
bake: {xy_step: 64, depth_samples: 4, z_max: 6}
YAML
"$ds" bake-library "$work/lib.yaml" --out "$work/lib" --shard 0/2 > "$work/s0.txt"
"$ds" bake-library "$work/lib.yaml" --out "$work/lib" --shard 1/2 > "$work/s1.txt"
[[ $(grep -c '^baked' "$work/s0.txt") -eq 2 && $(grep -c '^baked' "$work/s1.txt") -eq 2 ]]
[[ $(ls "$work"/lib/*.vdb | wc -l) -eq 4 ]]
# disjoint: no asset baked by both shards
[[ -z $(comm -12 <(grep '^baked' "$work/s0.txt" | sort) <(grep '^baked' "$work/s1.txt" | sort)) ]]
"$ds" bake-library "$work/lib.yaml" --out "$work/lib" | grep -q "baked 0, up to date 4"
"$ds" bake-library "$work/lib.yaml" --out "$work/lib" --force --dry-run | grep -c '^would bake' \
  | grep -qx 4
SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 "$ds" bake-library "$work/lib.yaml" \
  --out "$work/lib" | grep -q "shard 1/2: 2 of 4 assets; baked 0, up to date 2"
# the shipped manifest (paths relative to it) expands to 1 x 3 x 9 assets
"$ds" bake-library "$v/library.yaml" --out "$work/vl" --dry-run | grep -q "0/1: 27 of 27 assets"
echo "cameras: [$v/cameras/none.yaml]" > "$work/badlib.yaml"
echo "rigs: [$v/rigs/single-down.yaml]" >> "$work/badlib.yaml"
echo "waters: [jerlov:IB]" >> "$work/badlib.yaml"
expect_fail "manifest names a missing file" "$ds" bake-library "$work/badlib.yaml" --out "$work/lib2"

# A lamp at the camera centre (the backscatter integral diverges there; it used to run for
# minutes) is refused by every command that takes a rig, at once, with exit 2 and one line
# naming the lamp, its position and the limit. render takes the rig from the asset: see bake.
cat > "$work/centre-rig.yaml" <<YAML
rig:
  lights:
    - name: centre
      position: [0.0, 0.0, 0.0]
      direction: [0.0, 0.0, 1.0]
      intensity: [1.0, 1.0, 1.0]
YAML
echo "camera: {width: 16, height: 12, fx: 12.0, fy: 12.0, cx: 7.5, cy: 5.5}" > "$work/tiny.yaml"
"$ds" scene --out "$work/tiny" --frames 1 --camera "$work/tiny.yaml" >/dev/null
sed "s|$v/rigs/single-down.yaml|$work/centre-rig.yaml|; s|$v/cameras/none.yaml|$work/tiny.yaml|" \
  "$work/badlib.yaml" > "$work/centrelib.yaml"
near_field() {  # NAME CMD...: exit 2, the one-line message, in under 10 s, nothing written
  local name=$1; shift
  local t0=$SECONDS
  expect_fail "$name" "$@"
  (( SECONDS - t0 < 10 )) || { echo "FAIL $name: took $((SECONDS - t0)) s"; exit 1; }
  set +e; "$@" >/dev/null 2>&1; local rc=$?; set -e
  [[ $rc -eq 2 ]] || { echo "FAIL $name: exit $rc, expected 2"; exit 1; }
  local want="rig.lights[0].position: lamp 'centre' at [0, 0, 0] m is 0 m from the camera"
  want+=" centre, inside the near-field limit of 0.02 m"
  grep -qF "$want" "$work/err.txt" || { echo "FAIL $name: $(cat "$work/err.txt")"; exit 1; }
}
near_field "near-field lamp: bake" "$ds" bake --camera "$work/tiny.yaml" \
  --rig "$work/centre-rig.yaml" --water deep:clear -o "$work/centre.vdb"
near_field "near-field lamp: reference" "$ds" reference --camera "$work/tiny.yaml" \
  --rig "$work/centre-rig.yaml" --water deep:clear --rgb "$work/tiny/frame_0001.png" \
  --depth "$work/tiny/frame_0001_depth.exr" -o "$work/centre.exr"
near_field "near-field lamp: bake-library" "$ds" bake-library "$work/centrelib.yaml" \
  --out "$work/centrelib"
expect_absent "$work/centre.vdb" "$work/centre.exr"
[[ -z $(ls "$work/centrelib" 2>/dev/null) ]] || { echo "FAIL: bake-library wrote"; exit 1; }

# the deep-ocean presets bake from --water like the Jerlov ones
"$ds" bake --camera "$v/cameras/small-320.yaml" --rig "$v/rigs/authors-testset.yaml" \
  --water deep:nepheloid --xy-step 64 --depth-samples 4 -o "$work/deep.vdb" >/dev/null
"$ds" info "$work/deep.vdb" --json | grep -q '"deep-nepheloid"'
echo "bake CLI: OK"

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
# the shipped manifest (paths relative to it) expands to 1 x 3 x 6 assets
"$ds" bake-library "$v/library.yaml" --out "$work/vl" --dry-run | grep -q "0/1: 27 of 27 assets"
echo "cameras: [$v/cameras/none.yaml]" > "$work/badlib.yaml"
echo "rigs: [$v/rigs/single-down.yaml]" >> "$work/badlib.yaml"
echo "waters: [jerlov:IB]" >> "$work/badlib.yaml"
expect_fail "manifest names a missing file" "$ds" bake-library "$work/badlib.yaml" --out "$work/lib2"
echo "bake CLI: OK"

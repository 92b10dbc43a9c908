#!/usr/bin/env bash
# CLI conventions: --help shows the defaults, `deepsea help CMD` the same; every command that
# computes takes --threads (and honours it); usage errors (unknown command or option, a missing
# required option, a bad value) are one line on stderr and exit code 2, like config errors; a
# missing file is exit 4 in every command; -q silences progress and summaries, -v adds a line
# per frame; SIGINT and SIGTERM give 130; `%04d` and `####` frame patterns.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/cli_lib.sh"

# expect_usage NAME CMD...: one line on stderr, exit 2, a pointer to the right --help.
expect_usage() {
  local name=$1; shift
  expect_fail "$name" "$@"
  set +e; "$@" >/dev/null 2>&1; local rc=$?; set -e
  [[ $rc -eq 2 ]] || { echo "FAIL $name: exit $rc, want 2"; exit 1; }
  grep -q "(see deepsea.* --help)$" "$work/err.txt" || { echo "FAIL $name: no --help pointer"; exit 1; }
}

# --help: every command's help prints (exit 0); defaults are shown, including those that
# follow from other options and those the code fills in when a string is empty.
commands=$("$ds" --help | awk '/^Subcommands:/{on=1; next} on && NF {print $1}')
[[ $(wc -w <<<"$commands") -ge 9 ]] || { echo "FAIL: commands: $commands"; exit 1; }
for c in $commands; do
  "$ds" "$c" --help >"$work/help-$c.txt"
  # a command that computes takes --threads; import-config converts a text file, merge-shards
  # checks files
  if [[ $c != import-config && $c != merge-shards ]]; then
    grep -q -- "--threads INT=0 " "$work/help-$c.txt" || { echo "FAIL: $c --help has no --threads"; exit 1; }
  fi
done
for want in "bake:--xy-step INT=0" "bake:--depth-scheme TEXT=log" "bake:--z-max TEXT=auto" \
            "bake:--scattering TEXT=single" "render:--exposure TEXT=auto" "render:--bits INT:{8,16}=8" \
            "render:--depth-scale FLOAT:POSITIVE=0.001" "scene:--fx FLOAT=0.75\*width" \
            "scene:--frames INT:INT in \[1 - 100000\]=8" "demo:--scattering TEXT=multiple" "bench:--repeats INT=21" \
            "reference:--rel-tol FLOAT:POSITIVE=1e-07" "bake-library:--out TEXT=volumes/baked"; do
  grep -q -- "${want#*:}" "$work/help-${want%%:*}.txt" || { echo "FAIL: ${want%%:*} --help lacks '${want#*:}'"; cat "$work/help-${want%%:*}.txt"; exit 1; }
done
echo "ok --help shows defaults and --threads"

# Usage errors.
expect_usage no-command "$ds"
expect_usage unknown-command "$ds" nosuch
expect_usage unknown-option "$ds" scene --out "$work/s" --bogus
expect_usage missing-required "$ds" render --rgb a.png --depth d.exr -o x.png
expect_usage missing-positional "$ds" info
expect_usage bad-number "$ds" scene --out "$work/s" --frames abc
expect_usage bad-choice "$ds" render --asset a.vdb --rgb a.png --depth d.exr -o x.png --bits 9
expect_usage bad-threads "$ds" bake --config x.yaml -o x.vdb --threads -1
expect_usage bad-threads-text "$ds" render --asset a.vdb --rgb a.png --depth d.exr -o x.png --threads many
grep -q -- "--threads: must be an integer from 0" "$work/err.txt"
expect_absent "$work/s" x.vdb x.png

# --threads is honoured, and the result does not depend on it.
v=$src/volumes
cat >"$work/cam.yaml" <<'YAML'
camera: {width: 64, height: 48, fx: 48.0, fy: 48.0, cx: 31.5, cy: 23.5}
YAML
"$ds" scene --out "$work/in" --frames 2 --camera "$work/cam.yaml" --threads 1 >/dev/null
"$ds" bake --camera "$work/cam.yaml" --rig "$v/rigs/authors-testset.yaml" --water jerlov:IB \
  --xy-step 8 --depth-samples 8 -o "$work/a.vdb" --threads 2 >/dev/null
"$ds" info "$work/a.vdb" --threads 1 >/dev/null
for t in 1 2; do
  "$ds" render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr" \
    --layers "$work/t$t" --threads $t | grep -q "rendered 2 frame(s), skipped 0, failed 0"
done
# pixels, not bytes: OpenImageIO stamps each EXR header with the time it was written
/usr/bin/python3 - "$work/t1/frame_0002.exr" "$work/t2/frame_0002.exr" <<'PY'
import sys
import OpenImageIO as oiio
a, b = (oiio.ImageBuf(p) for p in sys.argv[1:3])
assert a.spec().channelnames == b.spec().channelnames, "channels differ"
assert (a.get_pixels(oiio.FLOAT) == b.get_pixels(oiio.FLOAT)).all(), "pixels differ"
PY
echo "ok --threads 1 and 2 give the same layers"

# `deepsea help [CMD]`: the --help text; an unknown command is a usage error.
for c in $commands; do
  cmp <("$ds" help "$c") "$work/help-$c.txt" || { echo "FAIL: help $c differs from $c --help"; exit 1; }
  grep -q "^Usage: deepsea $c " "$work/help-$c.txt" || { echo "FAIL: $c --help usage line"; exit 1; }
  grep -q -- "-q,--quiet" "$work/help-$c.txt" && grep -q -- "-v,--verbose" "$work/help-$c.txt" ||
    { echo "FAIL: $c has no -q/-v"; exit 1; }
done
cmp <("$ds" help) <("$ds" --help)
expect_usage "help nosuch" "$ds" help nosuch
echo "ok deepsea help CMD"

# A missing file: exit 4 (README) in every command that reads one.
expect_code() {
  local name=$1 want=$2; shift 2
  expect_fail "$name" "$@"
  set +e; "$@" >/dev/null 2>&1; local rc=$?; set -e
  [[ $rc -eq $want ]] || { echo "FAIL $name: exit $rc, want $want"; exit 1; }
}
f1=$work/in/frame_0001.png d1=$work/in/frame_0001_depth.exr rig=$v/rigs/authors-testset.yaml
expect_code "render: no asset" 4 "$ds" render --asset "$work/no.vdb" --rgb "$f1" --depth "$d1" -o "$work/x.png"
expect_code "render: no colour" 4 "$ds" render --asset "$work/a.vdb" --rgb "$work/no.png" --depth "$d1" -o "$work/x.png"
expect_code "reference: no depth" 4 "$ds" reference --camera "$work/cam.yaml" --rig "$rig" --water jerlov:IB \
  --rgb "$f1" --depth "$work/no.exr" -o "$work/x.png"
expect_code "bake: no rig" 4 "$ds" bake --camera "$work/cam.yaml" --rig "$work/no.yaml" --water jerlov:IB -o "$work/x.vdb"
expect_code "info: no asset" 4 "$ds" info "$work/no.vdb"
expect_code "import-config: no config" 4 "$ds" import-config "$work/no.yaml" -o "$work/x.yaml"
expect_code "bake-library: no manifest" 4 "$ds" bake-library "$work/no.yaml" --out "$work/lib"
expect_code "scene: no camera" 4 "$ds" scene --out "$work/s2" --camera "$work/no.yaml"
expect_code "demo: no config" 4 "$ds" demo --out "$work/d" --config "$work/no.yaml"
expect_code "merge-shards: no folder" 4 "$ds" merge-shards "$work/nofolder"
expect_absent "$work/x.png" "$work/x.vdb" "$work/x.yaml" "$work/lib" "$work/s2" "$work/d"
# A sequence whose frame is missing (a dangling link): the others are written, exit 6.
mkdir "$work/gap"; cp "$work"/in/frame_0001* "$work"/in/frame_0002_depth.exr "$work/gap/"
ln -s nowhere.png "$work/gap/frame_0002.png"
set +e; "$ds" render --asset "$work/a.vdb" --rgb "$work/gap/*.png" --depth "$work/gap/*_depth.exr" \
  -o "$work/gap_out" >/dev/null 2>"$work/err.txt"; rc=$?; set -e
[[ $rc -eq 6 && -s $work/gap_out/frame_0001.png ]] || { echo "FAIL: a sequence with a missing frame: exit $rc"; exit 1; }
grep -q "frame_0002.png: no such file" "$work/err.txt"
echo "ok a missing file: exit 4 everywhere; 6 for a sequence's frame"

# -q: nothing on stdout, errors still one line; -v: a line per frame.
seq=(render --asset "$work/a.vdb" --rgb "$work/in/*.png" --depth "$work/in/*_depth.exr")
[[ -z $("$ds" "${seq[@]}" -o "$work/q1" -q) ]] || { echo "FAIL: render -q printed"; exit 1; }
[[ -z $("$ds" -q "${seq[@]}" -o "$work/q2") ]] || { echo "FAIL: deepsea -q render printed"; exit 1; }
[[ -z $("$ds" scene --out "$work/q3" --frames 1 --camera "$work/cam.yaml" -q) ]] || { echo "FAIL: scene -q printed"; exit 1; }
[[ -z $("$ds" bake --camera "$work/cam.yaml" --rig "$rig" --water jerlov:IB --xy-step 8 \
  --depth-samples 8 -o "$work/q.vdb" -q 2>/dev/null) ]] || { echo "FAIL: bake -q printed"; exit 1; }
[[ -n $("$ds" info "$work/q.vdb" -q) ]] || { echo "FAIL: info -q printed nothing (its report is its output)"; exit 1; }
expect_fail "render -q with an error" "$ds" "${seq[@]}" -o "$work/in" -q
"$ds" "${seq[@]}" -o "$work/v1" -v >"$work/v.txt"
[[ $(grep -c "^rendered .*frame_000[12].png -> .*v1/frame_000[12].png$" "$work/v.txt") -eq 2 ]] || { echo "FAIL: render -v"; cat "$work/v.txt"; exit 1; }
"$ds" "${seq[@]}" -o "$work/v1" -v --resume >"$work/v.txt"
grep -q "^skipped .*frame_0002.png (its outputs are complete)" "$work/v.txt"
"$ds" scene --out "$work/v2" --frames 2 --camera "$work/cam.yaml" -v >"$work/v.txt"
[[ $(grep -c "^wrote .*frame_000[12].png, " "$work/v.txt") -eq 2 ]] || { echo "FAIL: scene -v"; exit 1; }
expect_usage "-q and -v" "$ds" "${seq[@]}" -o "$work/v3" -q -v
echo "ok -q and -v"

# Frame patterns: printf's %04d and ####, the numbered files that exist, as '*' does.
for p in '%04d' '####'; do
  "$ds" render --asset "$work/a.vdb" --rgb "$work/in/frame_$p.png" --depth "$work/in/frame_${p}_depth.exr" \
    -o "$work/pat" --exposure 50 -q
  "$ds" "${seq[@]}" -o "$work/star" --exposure 50 -q
  for f in frame_0001.png frame_0002.png; do cmp "$work/pat/$f" "$work/star/$f"; done
  rm -r "$work/pat" "$work/star"
done
echo "ok %04d and #### frame patterns"

# SIGINT and SIGTERM: exit 130 and one line in every command, also those that have no stop
# of their own (bench) and at any moment of those that do (scene).
for sig in INT TERM; do
  for cmd in "scene --out $work/sig --frames 1000" "bench --repeats 1000"; do
    rm -rf "$work/sig"
    "$ds" $cmd >/dev/null 2>"$work/sig.err" & pid=$!
    sleep 1; kill -$sig $pid
    set +e; wait $pid; rc=$?; set -e
    [[ $rc -eq 130 && $(wc -l <"$work/sig.err") -eq 1 ]] || { echo "FAIL: $cmd SIG$sig: exit $rc"; cat "$work/sig.err"; exit 1; }
  done
done
echo "ok SIGINT and SIGTERM: 130"
echo "cli conventions: OK"

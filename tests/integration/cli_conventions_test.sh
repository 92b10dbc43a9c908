#!/usr/bin/env bash
# CLI conventions: --help shows the defaults; every command that computes takes --threads (and
# honours it); usage errors (unknown command or option, a missing required option, a bad
# value) are one line on stderr and exit code 2, like config errors.
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
echo "cli conventions: OK"

#!/usr/bin/env bash
# Kills during `deepsea bake` and `deepsea bake-library` (issue 10, part 7). SIGINT and SIGTERM
# stop a bake with exit 130 and one line, writing nothing; SIGKILL leaves no partial asset (a
# bake writes only at the end, to a hidden temporary that is renamed). Running the same
# bake-library command again finishes the library with assets identical to an uninterrupted
# run: every byte but the random file UUID OpenVDB stamps and the hash that covers it.
set -euo pipefail
ds=$1 work=$2 src=$3
rm -rf "$work"; mkdir -p "$work"
cam=$src/volumes/cameras/small-320.yaml
rig=$src/volumes/rigs/authors-testset.yaml

# Same bytes but the UUID (OpenVDB's header, bytes 21..56) and the deepsea:integrity value.
same_asset() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
a, b = (open(p, "rb").read() for p in sys.argv[1:])
assert len(a) == len(b), "sizes differ: %d, %d" % (len(a), len(b))
def value_span(data):
    # OpenVDB metadata: name, then length-prefixed type name and value (little-endian int32)
    at = data.find(b"deepsea:integrity")
    assert at > 0, "no integrity record"
    at += len(b"deepsea:integrity")
    at += 4 + int.from_bytes(data[at:at + 4], "little")
    return at + 4, at + 4 + int.from_bytes(data[at:at + 4], "little")
lo, hi = value_span(a)
assert (lo, hi) == value_span(b), "the integrity records sit apart"
allowed = lambda i: 21 <= i < 57 or lo <= i < hi
diff = [i for i in range(len(a)) if a[i] != b[i] and not allowed(i)]
assert not diff, "%s and %s differ at %d byte(s), first at %d" % (*sys.argv[1:], len(diff), diff[0])
PY
  "$ds" info "$2" >/dev/null
}

# stop_after NAME SIG CMD...: runs CMD in the background (stdout and stderr in $work/NAME.out
# and .err, its output meant for $work/NAME/), sends SIG 1.5 s in and waits; sets rc (its exit
# code), took (seconds from the signal to the exit) and left (files in $work/NAME).
stop_after() {
  local name=$1 sig=$2 pid t0 t1; shift 2
  mkdir -p "$work/$name"
  set +e
  (exec "$@" >"$work/$name.out" 2>"$work/$name.err") &
  pid=$!
  sleep 1.5
  t0=$(date +%s.%N)
  kill -"$sig" "$pid"
  wait "$pid"; rc=$?
  t1=$(date +%s.%N)
  set -e
  took=$(python3 -c "print(f'{$t1 - $t0:.2f}')")
  left=$(find "$work/$name" -type f | wc -l)
}

# 1. bake, killed while it computes (1.5 s in; it takes several seconds); a stop lands within
# a second and a half (the stop flag is polled inside each column's quadrature).
for sig in INT TERM KILL; do
  stop_after "bake-$sig" "$sig" "$ds" bake --camera "$cam" --rig "$rig" --water jerlov:IB \
    --xy-step 4 -o "$work/bake-$sig/a.vdb"
  echo "bake SIG$sig: exit $rc, $left file(s) left, stopped in $took s"
  python3 -c "import sys; sys.exit(0 if $took < 1.5 else 1)" \
    || { echo "FAIL SIG$sig: took $took s to stop (limit 1.5 s)"; exit 1; }
  [[ $rc -ne 0 ]] || { echo "FAIL SIG$sig: the bake finished before the signal"; exit 1; }
  [[ $left -eq 0 ]] || { echo "FAIL SIG$sig: files left:"; find "$work/bake-$sig"; exit 1; }
  if [[ $sig != KILL ]]; then
    [[ $rc -eq 130 ]] || { echo "FAIL SIG$sig: exit $rc, expected 130"; cat "$work/bake-$sig.err"; exit 1; }
    [[ $(wc -l <"$work/bake-$sig.err") -eq 1 ]] && grep -q "stopped by signal.*nothing was written" \
      "$work/bake-$sig.err" || { echo "FAIL SIG$sig: stderr:"; cat "$work/bake-$sig.err"; exit 1; }
  fi
done

# 1b. The multiple-scattering stages (issue 29): a bake in its Monte Carlo columns, or in its
# lamp tables, that receives SIGTERM or SIGINT stops within a second, writes nothing and exits
# 130. It used to finish, write the asset and exit 0. The exact stage takes a fraction of a
# second here (coarse lattice, fixed z_max), so 1.5 s in the bake is in the Monte Carlo stage.
ms=(bake --camera "$cam" --rig "$rig" --water jerlov:IB --xy-step 32 --depth-samples 8
    --z-max 10 --no-check --scattering multiple)
for stage in "monte-carlo:--paths 4000000" "lamp-tables:--paths 1"; do
  for sig in TERM INT; do
    name=${stage%%:*}-$sig
    # shellcheck disable=SC2086
    stop_after "$name" "$sig" "$ds" "${ms[@]}" ${stage#*:} -o "$work/$name/a.vdb"
    echo "bake, $name: exit $rc, $left file(s) left, stopped in $took s"
    [[ $rc -eq 130 ]] || { echo "FAIL $name: exit $rc, expected 130"; cat "$work/$name.err"; exit 1; }
    [[ $left -eq 0 ]] || { echo "FAIL $name: files left:"; find "$work/$name"; exit 1; }
    [[ $(wc -l <"$work/$name.err") -eq 1 ]] && grep -q "stopped by signal.*nothing was written" \
      "$work/$name.err" || { echo "FAIL $name: stderr:"; cat "$work/$name.err"; exit 1; }
    python3 -c "import sys; sys.exit(0 if $took < 1.5 else 1)" \
      || { echo "FAIL $name: took $took s to stop (limit 1.5 s)"; exit 1; }
  done
done

# 2. bake-library: killed once its first asset is written, then run again.
mkdir -p "$work/lib"
cat >"$work/lib/library.yaml" <<YAML
cameras: [$cam]
rigs: [$rig]
waters: [$src/volumes/waters/jerlov-IB.yaml, $src/volumes/waters/jerlov-3C.yaml]
bake: {xy_step: 12}  # coarse: each bake takes about a second, the kill lands 0.3 s into the second
YAML
library() { "$ds" bake-library "$work/lib/library.yaml" --out "$work/lib/$1"; }
library ref >/dev/null
refs=$(find "$work/lib/ref" -name '*.vdb' | sort)
[[ $(echo "$refs" | wc -l) -eq 2 ]] || { echo "FAIL: the library has not 2 assets"; exit 1; }
for sig in INT TERM KILL; do
  out=$work/lib/$sig
  set +e
  (exec "$ds" bake-library "$work/lib/library.yaml" --out "$out" \
    >"$work/lib-$sig.out" 2>"$work/lib-$sig.err") &
  pid=$!
  set -e
  for _ in $(seq 1200); do
    [[ $(find "$out" -name '*.vdb' ! -name '.*' 2>/dev/null | wc -l) -ge 1 ]] && break
    sleep 0.05
  done
  sleep 0.3
  kill -"$sig" "$pid"
  set +e; wait "$pid"; rc=$?; set -e
  written=$(find "$out" -name '*.vdb' ! -name '.*' | wc -l)
  echo "bake-library SIG$sig: exit $rc, $written asset(s) written"
  [[ $written -eq 1 ]] || { echo "FAIL SIG$sig: expected 1 asset, found $written"; exit 1; }
  if [[ $sig != KILL ]]; then
    [[ $rc -eq 130 ]] || { echo "FAIL SIG$sig: exit $rc, expected 130"; cat "$work/lib-$sig.err"; exit 1; }
    [[ $(wc -l <"$work/lib-$sig.err") -eq 1 ]] && grep -q "stopped by signal" "$work/lib-$sig.err" \
      || { echo "FAIL SIG$sig: stderr:"; cat "$work/lib-$sig.err"; exit 1; }
    [[ -z $(find "$out" -name '.*') ]] || { echo "FAIL SIG$sig: hidden files left"; exit 1; }
  fi
  library "$sig" >"$work/lib-$sig.again"
  grep -q "baked 1, up to date 1, failed 0" "$work/lib-$sig.again" \
    || { echo "FAIL SIG$sig: the second run:"; cat "$work/lib-$sig.again"; exit 1; }
  for f in $refs; do same_asset "$f" "$out/$(basename "$f")"; done
  [[ -z $(find "$out" -name '.*') ]] || { echo "FAIL SIG$sig: hidden files after the second run"; exit 1; }
done
echo "PASS: kills during bake and bake-library leave only complete assets; the library finishes identical"

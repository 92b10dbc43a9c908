#!/usr/bin/env bash
# `cmake --install` into a scratch prefix installs the binary, the public headers only, the layer
# libraries, the CMake package, the pkg-config file and the Blender script; the installed
# binary runs and names nothing in the build tree (no RPATH/RUNPATH into it, every library it
# loads resolved outside it).
set -euo pipefail
cmake=$1 build=$2 prefix=$3 src=$4 version=$5
rm -rf "$prefix"
"$cmake" --install "$build" --prefix "$prefix" >/dev/null
fail() { echo "FAIL: $*"; exit 1; }

[[ -x $prefix/bin/deepsea ]] || fail "no bin/deepsea"
libdir=$(dirname "$(find "$prefix" -name deepseaConfig.cmake)")/../..
for layer in core colour optics camera asset io scene bake runtime batch reference live; do
  ls "$libdir"/libdeepsea_$layer.* >/dev/null 2>&1 || fail "no libdeepsea_$layer in $libdir"
done
for f in cmake/deepsea/deepseaConfig.cmake cmake/deepsea/deepseaConfigVersion.cmake \
         cmake/deepsea/deepseaTargets.cmake pkgconfig/deepsea.pc; do
  [[ -f $libdir/$f ]] || fail "no $f"
done
[[ -f $prefix/share/deepsea/blender/open_asset.py ]] || fail "no Blender script"
for f in demo.yaml library.yaml cameras/authors-800.yaml rigs/authors-testset.yaml \
         waters/deep-clear.yaml; do
  [[ -f $prefix/share/deepsea/$f ]] || fail "no example config share/deepsea/$f"
done
# The public headers only: <deepsea/deepsea.h> and the headers it includes, followed through
# the source tree (and deepsea/version.h, which CMake configures); none of the layers' own.
closure() {
  local todo=(deepsea/deepsea.h) seen=" " h inc
  while ((${#todo[@]})); do
    h=${todo[0]}; todo=("${todo[@]:1}")
    [[ $seen == *" $h "* ]] && continue
    seen+="$h "; echo "$h"
    [[ -f $src/include/$h ]] || continue
    while read -r inc; do todo+=("$inc"); done < <(sed -n 's/^#include "\(deepsea\/[^"]*\)".*/\1/p' "$src/include/$h")
  done
}
closure | sort >"$prefix/want.txt"
(cd "$prefix/include" && find deepsea -name '*.h' | sort) >"$prefix/got.txt"
cmp -s "$prefix/want.txt" "$prefix/got.txt" || { diff "$prefix/want.txt" "$prefix/got.txt"; fail "headers differ"; }
for private in core/atomic_file.h core/folder_lock.h batch/frame_jobs.h batch/output_folders.h; do
  [[ ! -e $prefix/include/deepsea/$private ]] || fail "private header $private installed"
done
# Each public header compiles on its own, warning-free: a user's -Wall -Wextra -Werror build.
cxx=${CXX:-c++}
while read -r h; do
  echo "#include <$h>" | "$cxx" -std=c++17 -Wall -Wextra -Wpedantic -Werror -fsyntax-only \
    -I"$prefix/include" -x c++ - || fail "$h does not compile alone with -Wall -Wextra -Werror"
done <"$prefix/got.txt"
layers=$(ls "$libdir"/libdeepsea_*.* | grep -v oiio | wc -l)
echo "ok layout: binary, $(wc -l <"$prefix/got.txt") headers (each compiles alone), $layers libraries, CMake package, pkg-config, Blender script, example configs"

# Nothing from the build tree: no run path into it, no library loaded from it.
build_abs=$(cd "$build" && pwd -P)
for f in "$prefix/bin/deepsea" "$libdir"/libdeepsea_*.so; do
  [[ -e $f ]] || continue
  if readelf -d "$f" | grep -E 'R(UN)?PATH' | grep -q -- "$build_abs"; then
    readelf -d "$f" | grep -E 'R(UN)?PATH'; fail "$f has a run path into the build tree"
  fi
  ldd "$f" >"$prefix/ldd.txt"
  if grep -q "not found" "$prefix/ldd.txt" || grep -q -- "$build_abs" "$prefix/ldd.txt"; then
    cat "$prefix/ldd.txt"; fail "$f loads a library that is missing or in the build tree"
  fi
done
echo "ok run paths: $(readelf -d "$prefix/bin/deepsea" | grep -E -c 'R(UN)?PATH') in bin/deepsea, none into $build_abs"

# The installed Blender script finds the installed binary by itself (bpy stubbed: no Blender).
found=$(env -u DEEPSEA PATH=/usr/bin:/bin /usr/bin/python3 - "$prefix/share/deepsea/blender/open_asset.py" <<'PY'
import importlib.util, sys, types
sys.modules["bpy"] = types.ModuleType("bpy")
spec = importlib.util.spec_from_file_location("open_asset", sys.argv[1])
m = importlib.util.module_from_spec(spec)
spec.loader.exec_module(m)
print(m.find_deepsea(None))
PY
)
[[ $found -ef $prefix/bin/deepsea ]] || fail "open_asset.py found '$found', not $prefix/bin/deepsea"
echo "ok Blender script: finds $found"

[[ $("$prefix/bin/deepsea" --version) == "deepsea $version" ]] || fail "--version"

# OpenImageIO's module: installed, and the one the installed binary loads (a .tif output is
# checked for a writer before the asset is opened).
[[ -f $libdir/deepsea/libdeepsea_oiio.so ]] || fail "no deepsea/libdeepsea_oiio.so in $libdir"
rm -f "$prefix"/ld.*
LD_DEBUG=files LD_DEBUG_OUTPUT="$prefix/ld" "$prefix/bin/deepsea" render --asset "$prefix/no.vdb" \
  --rgb x.png --depth x.exr -o "$prefix/x.tif" >/dev/null 2>&1 || true
module=$(grep -h -o "file=[^ ]*libdeepsea_oiio.so" "$prefix"/ld.* | head -1 | cut -d= -f2)
[[ -n $module && $module -ef $libdir/deepsea/libdeepsea_oiio.so ]] \
  || fail "the installed binary loaded '${module:-no module}', not the installed one"
echo "ok OpenImageIO module: $module"
"$prefix/bin/deepsea" import-config --help >/dev/null
echo "package install: OK"

# Sourced by the Cycles tests: skips (77) where Blender or Debian's python3 with numpy and
# OpenImageIO is absent; sets $py and a fresh $work.
command -v blender >/dev/null || { echo "SKIP: blender is not installed"; exit 77; }
py=/usr/bin/python3
[[ -x $py ]] && $py -c 'import numpy, OpenImageIO' 2>/dev/null || {
  echo "SKIP: $py with numpy and OpenImageIO is not available"; exit 77; }
rm -rf "$work"; mkdir -p "$work"

#!/usr/bin/env bash
# The project's own .clang-format is applied to every C++ file (Debian's clang-format 14;
# scripts/install-deps.sh --tests installs it). Fix with: clang-format -i <the files listed>.
set -euo pipefail
ds=$1 work=$2 src=$3
command -v clang-format >/dev/null || { echo "FAIL: clang-format is not installed (scripts/install-deps.sh --tests installs it)"; exit 1; }
cd "$src"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.h')
else
  mapfile -t files < <(find include src tools tests -name '*.cpp' -o -name '*.h')
fi
((${#files[@]} > 50)) || { echo "FAIL: found only ${#files[@]} C++ files"; exit 1; }
bad=$(clang-format --dry-run "${files[@]}" 2>&1 | grep -oE '^[^:]+\.(cpp|h):' | sort -u || true)
if [[ -n $bad ]]; then
  echo "FAIL: not formatted with .clang-format:"; echo "$bad"; exit 1
fi
echo "format: ${#files[@]} files OK"

#!/usr/bin/env bash
# Sorts the crash inputs a fuzzer left in a folder (crash-*, oom-*, leak-*, timeout-*): each is
# replayed, and the crash is third-party when the innermost frame of its report that is not
# the sanitizer runtime, libc or libstdc++ lies in OpenVDB or Blosc (the decoders that trust
# lengths in a file whose integrity record was forged), else it is deepsea's and fails.
#   scripts/triage-crashes.sh FUZZ_BINARY FOLDER
set -uo pipefail
bin=$1 dir=$2
ours=0 theirs=0
for f in "$dir"/crash-* "$dir"/oom-* "$dir"/leak-* "$dir"/timeout-*; do
  [[ -e $f ]] || continue
  # -malloc_limit_mb: an allocation over 1 GB is reported where it is made, with its whole
  # stack; an input that only crosses the RSS limit is reported from the RSS watcher, whose
  # stack names no caller (a 1.7 GB string in OpenVDB's MetaMap::readMeta was filed as ours).
  report=$("$bin" -rss_limit_mb=3072 -malloc_limit_mb=1024 -timeout=60 "$f" 2>&1)
  frame=$(echo "$report" | grep -E '^ +#[0-9]+ ' |
    grep -vE ' in (__asan|__sanitizer|__interceptor_|__lsan|__ubsan|operator new|operator delete|malloc|calloc|realloc|free|mem(cpy|move|set)|abort|raise|__GI_|fuzzer::)' |
    grep -vE '\((/lib/x86_64-linux-gnu/)?(libc|libstdc\+\+)\.so' | head -1)
  if [[ -z $frame ]] && ! echo "$report" | grep -qE 'ERROR|runtime error|deadly signal|out-of-memory'; then
    continue  # no longer reproduces
  fi
  if echo "$frame" | grep -qE 'openvdb|blosc|libz\.so'; then
    theirs=$((theirs + 1))
    echo "third-party: $(basename "$f"): $(echo "$frame" | sed -E 's/^ +#[0-9]+ 0x[0-9a-f]+ in //' | cut -c1-160)"
  else
    ours=$((ours + 1))
    echo "DEEPSEA: $(basename "$f"):"
    echo "$report" | grep -E 'ERROR|runtime error|^ +#[0-9]+ ' | head -20
  fi
done
echo "$(basename "$bin"): $theirs third-party crash input(s), $ours in deepsea"
((ours == 0))

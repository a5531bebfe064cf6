#!/usr/bin/env bash
# Compiler launcher for scripts/profile-build.sh: runs the compile it is given and appends
# "seconds<TAB>object file" to $BEMSURG_COMPILE_LOG.
out=""
prev=""
for a in "$@"; do
  [ "$prev" = "-o" ] && out="$a"
  prev="$a"
done
s=$(date +%s%N)
"$@"
rc=$?
e=$(date +%s%N)
printf '%d.%03d\t%s\n' $(( (e - s) / 1000000000 )) $(( (e - s) / 1000000 % 1000 )) "$out" >> "${BEMSURG_COMPILE_LOG:?}"
exit $rc

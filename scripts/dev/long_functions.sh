#!/usr/bin/env bash
# Lists the C functions longer than a limit (CONTRIBUTING.md: functions under ~100 lines), one
# "lines file:line name" a line, longest first, then their count. A function is what clang-format
# lays out in this tree: its name on a line that opens a parameter list, then "{" alone at the
# start of a line, the body, and "}" alone at the start of a line; its length is the lines from
# that "{" to that "}", both included.
#   scripts/dev/long_functions.sh [-n LIMIT] [FOLDER...]   (LIMIT 100; FOLDERS app render sim)
set -euo pipefail
limit=100
if [ "${1:-}" = "-n" ]; then
  limit=${2:?usage: long_functions.sh [-n LIMIT] [FOLDER...]}
  shift 2
fi
cd "$(dirname "$0")/../.."
[ $# -gt 0 ] || set -- app render sim
find "$@" -name '*.c' -print0 | sort -z | xargs -0 awk -v limit="$limit" '
  FNR == 1 { open = 0; name = "" }
  !open && match($0, /[A-Za-z_][A-Za-z0-9_]*[(]/) && $0 !~ /^[ \t]/ {
    name = substr($0, RSTART, RLENGTH - 1)
  }
  /^[{]/ && !open { open = 1; first = FNR; next }
  /^[}]/ && open {
    open = 0
    if (FNR - first + 1 > limit)
      printf "%d %s:%d %s\n", FNR - first + 1, FILENAME, first, name
  }' | sort -rn | awk '{ print } END { printf "%d functions over '"$limit"' lines\n", NR }'

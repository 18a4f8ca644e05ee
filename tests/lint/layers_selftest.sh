#!/usr/bin/env bash
# The rule no-circles of layers.sh on small trees: a circle of includes and a circle of calls are
# found (exit 1, the arrows named), a tree without one passes, and a name inside a comment or a
# string is no call.
set -euo pipefail
layers="$(cd "$(dirname "$0")" && pwd)/layers.sh"
tree=$(mktemp -d)
trap 'rm -rf "$tree"' EXIT
fail() {
  echo "layers_selftest: $*" >&2
  exit 1
}
# expect STATUS PATTERN: runs the rule on $tree, wants that exit status and PATTERN in its output
expect() {
  local status=0 out
  out=$(bash "$layers" no-circles "$tree" 2>&1) || status=$?
  [ "$status" = "$1" ] || fail "exit $status, wanted $1: $out"
  grep -qE -- "$2" <<<"$out" || fail "no '$2' in: $out"
}

mkdir -p "$tree/sim" "$tree/app/fam"
# a chain, no circle: source A calls source B's function and includes B's header, B includes A's
# header for a type and names a_first only in a comment and a string
printf '#include "b.h"\nint a_first(void)\n{\n    return b_second();\n}\n' >"$tree/sim/a.c"
printf 'typedef int A;\nint a_first(void);\n' >"$tree/sim/a.h"
printf '#include "a.h"\n/* not a_first */\nint b_second(void)\n{\n    return (int)sizeof "a_first()";\n}\n' \
  >"$tree/sim/b.c"
printf 'int b_second(void);\n' >"$tree/sim/b.h"
expect 0 'no-circles: ok'

# a circle of calls: B now calls a_first
printf '#include "a.h"\nint b_second(void)\n{\n    return a_first() - 1;\n}\n' >"$tree/sim/b.c"
expect 1 'sim/b.c:4: calls a_first'
expect 1 'sim/a.c:4: calls b_second'
printf '#include "a.h"\nint b_second(void)\n{\n    return 1;\n}\n' >"$tree/sim/b.c"
expect 0 'no-circles: ok'

# a circle of includes, across folders (a family header by its bare name, the core's by path)
printf '#include "app/core.h"\n' >"$tree/app/fam/fam.h"
printf '#include "fam/fam.h"\n' >"$tree/app/core.h"
expect 1 'app/core.h:1: #include "fam/fam.h"'
expect 1 'app/fam/fam.h:1: #include "app/core.h"'
printf '\n' >"$tree/app/core.h"
expect 0 'no-circles: ok'
echo "layers_selftest: ok"

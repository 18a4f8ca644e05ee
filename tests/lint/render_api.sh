#!/usr/bin/env bash
# render's installed headers (render/render.h, render_image.h, render_style.h) declare only what a
# program outside render/ calls: every function they declare must be named by a source file
# outside render/ (app/, python/, examples/, tests/ but tests/render/). render's own tests and the
# benchmarks (bench/) measure its inside and include render/internal.h, so they do not count.
# Prints each function no outside file uses, and exits 1 when there is any. Run from anywhere.
set -euo pipefail
cd "$(dirname "$0")/../.."

headers=(render/render.h render/render_image.h render/render_style.h)
mapfile -t functions < <(grep -hoE '^[A-Za-z_][A-Za-z0-9_ *]*[ *]render_[a-z0-9_]+[(]' "${headers[@]}" |
  sed -E 's/.*[ *](render_[a-z0-9_]+)[(]$/\1/' | sort -u)
[ ${#functions[@]} -gt 0 ] || { echo "render_api.sh: no functions found in ${headers[*]}" >&2; exit 2; }

# the source files outside render/, tests/render/, bench/ and build or output folders
mapfile -t sources < <(find . \( -path ./render -o -path ./tests/render -o -path ./bench \
  -o -path './build*' -o -path ./out -o -path ./.git \) -prune -o -type f \
  \( -name '*.c' -o -name '*.h' -o -name '*.cpp' -o -name '*.py' \) -print)

unused=()
for f in "${functions[@]}"; do
  grep -qw -- "$f" "${sources[@]}" || unused+=("$f")
done
if [ ${#unused[@]} -gt 0 ]; then
  echo "render/render.h (installed) declares functions no program outside render/ calls;"
  echo "move them to render/internal.h:"
  printf '  %s\n' "${unused[@]}"
  exit 1
fi
echo "render API: ok (${#functions[@]} public functions, each called outside render/)"

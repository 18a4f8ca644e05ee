#!/usr/bin/env bash
# Layering rules of docs/dev/architecture.md, one rule per call, run from the repository root:
#   layers.sh render-no-app   render/ never includes an app/ header
#   layers.sh core-no-family  the app core (app/ but the family folders) includes no family header
#   layers.sh families-apart  a family folder app/F/ never includes another family's header
#   layers.sh sources-below-run  app/scene/sources.[ch] (used by the run and the scene loader) include
#                             no run.h and name no function that app/run/run.c or app/scene/scene_load.c
#                             defines: no circle run -> sources -> run or scene_load -> sources
#                             -> scene_load
#   layers.sh layers-order    a core folder includes only the folders below it: cli > driver > run
#                             > output > scene > base (a header of a higher folder named by path,
#                             "run/run.h" or "app/run/run.h", from a lower one fails)
#   layers.sh no-circles      no circle among the files of sim/, render/ and app/: no file
#                             includes itself through others, and no two sources call each
#                             other, directly or through others (the arrows of circles.awk)
# A second argument names the tree to check (the repository by default; the self-test of
# no-circles, layers_selftest.sh, hands it small trees with and without a circle).
# A family is a folder app/F/ whose F.c defines app_F_experiment. An include names a header by path
# ("bne/bne.h", "app/bne/bne.h") or, from a file of the same folder, by its bare name ("bne.h").
# Prints each offending line as file:line: include, and exits 1 when there is any.
set -euo pipefail
rule=${1:?usage: layers.sh render-no-app|core-no-family|families-apart|sources-below-run|layers-order|no-circles [TREE]}
here=$(cd "$(dirname "$0")" && pwd)
cd "${2:-$here/../..}"

# a family: a folder app/F/ whose F.c defines its hook table app_F_experiment; the other folders
# (the layers: base/, scene/, run/, output/, driver/, cli/) are the app core
families=()
for d in app/*/; do
  f=$(basename "$d")
  if [ -d "$d" ] && grep -qs "AppExperiment app_${f}_experiment\b" "app/$f/$f.c"; then
    families+=("$f")
  fi
done

# headers_of DIR...: the bare names of the headers under DIR
headers_of() {
  find "$@" -name '*.h' -printf '%f\n' | sort -u
}

# offending FILES -- NAMES...: include lines of FILES naming any of NAMES (path or bare name)
offending() {
  local files=() names=()
  while [ "$1" != "--" ]; do files+=("$1"); shift; done
  shift
  names=("$@")
  [ ${#files[@]} -gt 0 ] && [ ${#names[@]} -gt 0 ] || return 0
  local alternatives
  alternatives=$(printf '%s\n' "${names[@]}" | sed 's/[.]/\\./g' | paste -sd'|')
  grep -nHE "^[[:space:]]*#[[:space:]]*include[[:space:]]*\"([^\"]*/)?(${alternatives})\"" \
    "${files[@]}" || true
}

found=""
case "$rule" in
render-no-app)
  mapfile -t names < <(headers_of app)
  mapfile -t files < <(find render -name '*.[ch]')
  found=$(offending "${files[@]}" -- "${names[@]}")
  found=$(
    {
      echo "$found"
      grep -nHE '^[[:space:]]*#[[:space:]]*include[[:space:]]*"(\.\./)*app/' "${files[@]}" || true
    } | sed '/^$/d' | sort -u
  )
  ;;
core-no-family)
  dirs=()
  for f in "${families[@]}"; do dirs+=("app/$f"); done
  prune=()
  for d in "${dirs[@]}"; do prune+=(-path "$d" -prune -o); done
  mapfile -t files < <(find app "${prune[@]}" -name '*.[ch]' -print)
  mapfile -t names < <(headers_of "${dirs[@]}")
  found=$(offending "${files[@]}" -- "${names[@]}")
  ;;
families-apart)
  for f in "${families[@]}"; do
    others=()
    for g in "${families[@]}"; do [ "$g" = "$f" ] || others+=("app/$g"); done
    [ ${#others[@]} -gt 0 ] || continue
    mapfile -t names < <(headers_of "${others[@]}")
    mapfile -t files < <(find "app/$f" -name '*.[ch]')
    found+=$(offending "${files[@]}" -- "${names[@]}")$'\n'
  done
  ;;
sources-below-run)
  files=(app/scene/sources.c app/scene/sources.h)
  found=$(offending "${files[@]}" -- run.h scene_load.h)
  # the functions defined at file scope (a name and "(" after a type, at the start of a line)
  mapfile -t names < <(grep -hoE '^[A-Za-z_][A-Za-z0-9_ *]*[ *]((app|scene|loader)_[A-Za-z0-9_]+)[(]' \
    app/run/run.c app/scene/scene_load.c | sed -E 's/.*[ *]([A-Za-z0-9_]+)[(]$/\1/' | sort -u)
  if [ ${#names[@]} -gt 0 ]; then
    found+=$'\n'$(grep -nHwE "$(IFS='|'; echo "${names[*]}")" "${files[@]}" || true)
  fi
  ;;
layers-order)
  # the core folders, lowest first (the table of docs/dev/architecture.md)
  order=(base scene output run driver cli)
  for i in "${!order[@]}"; do
    higher=("${order[@]:i+1}")
    [ ${#higher[@]} -gt 0 ] || continue
    mapfile -t files < <(find "app/${order[$i]}" -name '*.[ch]')
    [ ${#files[@]} -gt 0 ] || continue
    found+=$(grep -nHE "^[[:space:]]*#[[:space:]]*include[[:space:]]*\"(app/)?($(
      IFS='|'
      echo "${higher[*]}"
    ))/" "${files[@]}" || true)$'\n'
  done
  ;;
no-circles)
  mapfile -t files < <(find sim render app -name '*.[ch]' 2>/dev/null | sort)
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  printf '%s\n' "${files[@]}" >"$tmp/files"
  : >"$tmp/edges"
  : >"$tmp/why"
  dirs="app ."
  for f in "${families[@]}"; do dirs+=" app/$f"; done
  if [ ${#files[@]} -gt 0 ]; then
    awk -v list_file="$tmp/files" -v include_dirs="$dirs" -v edges_file="$tmp/edges" \
      -v why_file="$tmp/why" -f "$here/circles.awk" "${files[@]}" pass=2 "${files[@]}"
  fi
  # tsort names the files of each circle it breaks; each circle is printed with its arrows
  found=$({ tsort "$tmp/edges" 2>&1 >/dev/null || true; } | awk -F '\t' -v why="$tmp/why" '
    BEGIN { while ((getline l < why) > 0) { split(l, p, "\t"); arrow[p[1]] = p[2] } }
    function flush(a, b) {
      if (n == 0) return
      print "circle:" members
      for (a = 1; a <= n; ++a) for (b = 1; b <= n; ++b)
        if ((m[a] " " m[b]) in arrow) print "  " arrow[m[a] " " m[b]]
      n = 0; members = ""
    }
    /input contains a loop/ { flush(); next }
    { sub(/^tsort: /, ""); m[++n] = $0; members = members " " $0 }
    END { flush() }')
  ;;
*)
  echo "layers.sh: unknown rule $rule" >&2
  exit 2
  ;;
esac
found=$(echo "$found" | sed '/^$/d')
if [ -n "$found" ]; then
  echo "layering rule $rule broken (docs/dev/architecture.md):"
  echo "$found"
  exit 1
fi
echo "layering rule $rule: ok (families: ${families[*]})"

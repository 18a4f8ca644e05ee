# SPDX-License-Identifier: MIT
# same_outputs.sh, sourced by CLI test scripts (cli.resume, cli.hard.resume_threads); the caller
# defines fail MESSAGE.
# same A B [MIN]: every .state and .csv of run A is in B with the same bytes (at least MIN
# compared, 6 unless given)
same() {
  local a=$1 b=$2 min=${3:-6} n=0
  for f in "$a"/*.state "$a"/*.csv; do
    cmp -s "$f" "$b/${f#"$a"/}" || fail "$b/${f#"$a"/} differs from $f"
    n=$((n + 1))
  done
  [ "$n" -ge "$min" ] || fail "only $n outputs compared"
}

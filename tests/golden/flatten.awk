# SPDX-License-Identifier: MIT
# Flattens one output file into records "LINE<TAB>FIELD<TAB>VALUE" for compare.sh.
#   awk -v mode=csv|headerless|json -v out=DIR -v rel=PATH -f flatten.awk FILE
# csv: the first line names the columns (FIELD = the column's name, or #k past the header;
# lines starting with # are compared whole); headerless: FIELD = #k (1-based); json: FIELD =
# the value's path (stages[1].wall_seconds). Timing fields print as "(ignored)" (see
# ignored()); the run's output folder `out` inside a value is replaced by @OUT@.
function ignored(name, path) {
  # wall-clock timings: differ between runs and machines
  if (name == "wall_seconds" || name == "particle_steps_per_second") return 1
  # the threads the step ran on (summary.json): the results are the same bits on any count
  if (mode == "json" && path == "threads") return 1
  # build versions (summary.json)
  if (path == "versions" || index(path, "versions.") == 1) return 1
  # the member's output folder (sweep.csv): an absolute path
  if (mode == "csv" && name == "dir") return 1
  # header-less study sample files: their last timing column
  if (mode == "headerless" && rel ~ /(^|\/)samples\/s[0-9]+\.csv$/ && name == "#17") return 1
  if (mode == "headerless" && rel ~ /(^|\/)samples\/s[0-9]+\.dep$/ && name == "#11") return 1
  return 0
}
function clean(v,    k) {
  if (out != "") {
    while ((k = index(v, out)) > 0)
      v = substr(v, 1, k - 1) "@OUT@" substr(v, k + length(out))
  }
  return v
}
function emit(line, name, path, v) {
  # provenance (summary.json): the command line, date, host and revision of this very run; the
  # thread counts it chose by measurement (after the provenance, so no line moves)
  if (mode == "json" && (path == "provenance" || index(path, "provenance.") == 1)) return
  if (mode == "json" && index(path, "thread_choices.") == 1) return
  if (ignored(name, path)) v = "(ignored)"
  else v = clean(v)
  printf "%d\t%s\t%s\n", line, path, v
}
# split a CSV line into f[1..n], honouring "quoted, fields"
function csv_split(s, f,    n, i, c, q, cur) {
  n = 0; cur = ""; q = 0
  for (i = 1; i <= length(s); ++i) {
    c = substr(s, i, 1)
    if (q) {
      if (c == "\"") {
        if (substr(s, i + 1, 1) == "\"") { cur = cur c; ++i } else q = 0
      }
      else cur = cur c
    } else if (c == "\"") q = 1
    else if (c == ",") { f[++n] = cur; cur = "" }
    else cur = cur c
  }
  f[++n] = cur
  return n
}
mode == "csv" || mode == "headerless" {
  sub(/\r$/, "")
  if (mode == "csv" && NR == 1) {
    nh = csv_split($0, head)
    for (i = 1; i <= nh; ++i) emit(NR, "#header", "#header" i, head[i])
    next
  }
  if (substr($0, 1, 1) == "#") { emit(NR, "#comment", "#comment", $0); next }
  n = csv_split($0, f)
  for (i = 1; i <= n; ++i) {
    name = (mode == "csv" && i <= nh) ? head[i] : "#" i
    # key,value tables (observables.csv): name the value by its key
    if (mode == "csv" && nh == 2 && head[1] == "key" && head[2] == "value" && i == 2) name = "value[" f[1] "]"
    emit(NR, name, name, f[i])
  }
  next
}
mode == "json" { text = text $0 "\n"; next }
END {
  if (mode != "json") exit
  line = 1; depth = 0; len = length(text); expect_key = 0
  for (i = 1; i <= len; ++i) {
    c = substr(text, i, 1)
    if (c == "\n") { ++line; continue }
    if (c == " " || c == "\t" || c == "\r" || c == ",") {
      if (c == "," && depth > 0 && type[depth] == "a") ++idx[depth]
      if (c == "," && depth > 0 && type[depth] == "o") expect_key = 1
      continue
    }
    if (c == ":") continue
    if (c == "{" || c == "[") {
      ++depth; type[depth] = (c == "{") ? "o" : "a"; idx[depth] = 0; key[depth] = ""
      expect_key = (c == "{"); continue
    }
    if (c == "}" || c == "]") { --depth; expect_key = 0; continue }
    # a scalar: string, number, true, false, null
    if (c == "\"") {
      v = ""
      for (++i; i <= len; ++i) {
        c = substr(text, i, 1)
        if (c == "\\") { v = v c substr(text, i + 1, 1); ++i; continue }
        if (c == "\"") break
        v = v c
      }
      v = "\"" v "\""
    } else {
      v = ""
      for (; i <= len; ++i) {
        c = substr(text, i, 1)
        if (c ~ /[],} \t\r\n:]/) { --i; break }
        v = v c
      }
    }
    if (depth > 0 && type[depth] == "o" && expect_key) {
      key[depth] = substr(v, 2, length(v) - 2); expect_key = 0; continue
    }
    path = ""; name = ""
    for (d = 1; d <= depth; ++d) {
      if (type[d] == "o") { path = path (path == "" ? "" : ".") key[d]; name = key[d] }
      else path = path "[" idx[d] "]"
    }
    if (depth == 0) path = "(top)"
    emit(line, name, path, v)
  }
}

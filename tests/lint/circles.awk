# circles.awk: the arrows between the files of a tree, for layers.sh no-circles. A file A points
# at B when A includes B (`#include "B"`, resolved from A's folder, then from each folder of
# include_dirs), or when A is a source (.c) that names a function which B, a source, alone
# defines (external, at file scope). The files come twice on the command line: once to read the
# definitions, then, after the assignment pass=2, to read the includes and the names.
# Variables: list_file (the files, one a line), include_dirs (space-separated folders),
# edges_file (written: "A B" a line, for tsort), why_file (written: "A B<TAB>file:line: what").
BEGIN {
    while ((getline f < list_file) > 0)
        files[f] = 1
    n = split(include_dirs, ds, " ")
    for (k = 1; k <= n; ++k)
        incdirs[ds[k]] = 1
    pass = 1
}

# line without its comments and string and character literals (incomment: inside /* */, kept
# from one line to the next)
function strip(line, out, tok, c, e)
{
    out = ""
    while (length(line) > 0) {
        if (incomment) {
            e = index(line, "*/")
            if (!e)
                return out
            line = substr(line, e + 2)
            incomment = 0
            continue
        }
        if (match(line, /\/\*|\/\/|"|'/) == 0)
            return out line
        out = out substr(line, 1, RSTART - 1)
        tok = substr(line, RSTART, RLENGTH)
        line = substr(line, RSTART + RLENGTH)
        if (tok == "//")
            return out
        if (tok == "/*") {
            incomment = 1
            continue
        }
        while (length(line) > 0) { # the literal, to its closing quote
            c = substr(line, 1, 1)
            line = substr(line, 2)
            if (c == "\\")
                line = substr(line, 2)
            else if (c == tok)
                break
        }
        out = out " "
    }
    return out
}

function arrow(from, to, what)
{
    if (from != to && !((from " " to) in edge))
        edge[from " " to] = FILENAME ":" FNR ": " what
}

FNR == 1 {
    incomment = 0
    dir = FILENAME
    sub(/\/[^\/]*$/, "", dir)
}

pass == 1 {
    line = strip($0)
    if (FILENAME ~ /\.c$/ && line !~ /^(static|typedef|extern)/ && line !~ /;[ \t]*$/ &&
        match(line, /^[A-Za-z_][A-Za-z0-9_ *]*[ *][A-Za-z_][A-Za-z0-9_]*\(/)) {
        name = substr(line, RSTART, RLENGTH - 1)
        sub(/.*[ *]/, "", name)
        if (!(name in owner))
            owner[name] = FILENAME
        else if (owner[name] != FILENAME)
            owner[name] = "" # two files define it: no arrow
    }
    next
}

{
    line = strip($0)
    if (line ~ /^[ \t]*#[ \t]*include[ \t]*/) {
        if (match($0, /"[^"]+"/)) {
            inc = substr($0, RSTART + 1, RLENGTH - 2)
            target = ""
            if ((dir "/" inc) in files)
                target = dir "/" inc
            else if (inc in files)
                target = inc
            else
                for (d in incdirs)
                    if ((d "/" inc) in files) {
                        target = d "/" inc
                        break
                    }
            if (target != "")
                arrow(FILENAME, target, "#include \"" inc "\"")
        }
        next
    }
    if (FILENAME !~ /\.c$/)
        next # a header declares; the calls are in the sources
    n = split(line, words, /[^A-Za-z0-9_]+/)
    for (k = 1; k <= n; ++k)
        if ((words[k] in owner) && owner[words[k]] != "")
            arrow(FILENAME, owner[words[k]], "calls " words[k])
}

END {
    for (e in edge) {
        print e > edges_file
        print e "\t" edge[e] > why_file
    }
}

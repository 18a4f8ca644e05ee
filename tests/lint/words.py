#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Words that are true: what the comments and the docs name must exist.

    words.py paths    every repository path named in a code comment (C, C++, CMake, shell,
                      Python) or a doc (README.md, CONTRIBUTING.md, docs/**/*.md) exists: a name
                      that starts with a top folder of the repository (app/run/run.c, sim/sim.h,
                      scenes/crater/, docs/scenes.md), a relative Markdown link of a doc, and
                      the name a C file gives itself at the top of its opening comment
                      ("/* run.c: ..."), which must be its own, and a file named bare
                      (run.c, sim.h, quick.scene), which must be a file of the repository
                      somewhere or, for a header, a system header
    words.py refs     no comment or doc cites an issue or pull-request number ("issue 38",
                      "#38") or notes kept outside the repository (../shared/notes)
    words.py fixture  both rules on tests/lint/fixtures/words/, a small tree with one defect of
                      each kind: they must find exactly the lines of its expected.txt

Paths under output folders (out/, build/) are not checked, nor globs (app/*.c) and placeholders
(docs/<name>.md, tests/golden/CASE); a program's name (bench/bench_stream) stands for its source. Names that are examples rather than files of the repository are listed with
a reason in tests/lint/words_allow.txt. Prints file:line: what, and exits 1 when there is any.
"""
import os
import re
import subprocess
import sys

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
FIXTURE = os.path.join(REPO, "tests", "lint", "fixtures", "words")
SKIP_DIRS = {".git", "out", "node_modules", "__pycache__"}
CODE_EXT = {".c", ".h", ".cpp", ".cc", ".py", ".sh", ".cmake"}
ROOT = REPO
PATH_RE = None
BASENAMES = set()
BARE_RE = re.compile(r"(?<![\w/.\-*~$@<])([A-Za-z_][\w\-]*\.(?:c|h|md|sh|py|scene))(?![\w/])")


def set_root(root):
    """Reads the tree at root: its top folders start the paths the lint checks."""
    global ROOT, PATH_RE
    ROOT = root
    BASENAMES.clear()
    for dirpath, dirnames, filenames in os.walk(ROOT):
        dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS and not d.startswith(".")
                       and not (dirpath == ROOT and d.startswith("build"))]
        BASENAMES.update(filenames)
    top = sorted(
        d for d in os.listdir(ROOT)
        if os.path.isdir(os.path.join(ROOT, d)) and not d.startswith(".") and d not in SKIP_DIRS
        and not d.startswith("build"))
    # a path: a top folder, then name characters; not glued to what comes before
    # (include/sablier/sim/sim.h names no sim/sim.h)
    PATH_RE = re.compile(r"(?<![\w/.\-~$@])((?:%s)/[\w./\-+]*)" % "|".join(map(re.escape, top)))

PLACEHOLDER_RE = re.compile(r"(?<![A-Z])[A-Z]+(?=[./\-_]|$)")
LINK_RE = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")
SELF_RE = re.compile(r"\A\s*(?:/\*[^\n]*?\n?\s*)?/\*\s*([\w\-]+\.(?:c|h|cpp)):")
ISSUE_RE = re.compile(r"\b(?:issues?|PR|pull request)\s*#?\s*\d+|(?<![\w&#/])#\d{1,4}\b", re.I)
NOTES_RE = re.compile(r"(?:\.\./)+shared\b|shared/notes|\bnotes/[\w.\-]+\.md")


def files():
    for dirpath, dirnames, filenames in os.walk(ROOT):
        rel_dir = os.path.relpath(dirpath, ROOT)
        dirnames[:] = sorted(
            d for d in dirnames
            if d not in SKIP_DIRS and not (rel_dir == "." and d.startswith("build"))
            and not d.startswith("."))
        for name in sorted(filenames):
            rel = os.path.normpath(os.path.join(rel_dir, name))
            ext = os.path.splitext(name)[1]
            if ext == ".md" or ext in CODE_EXT or name == "CMakeLists.txt":
                yield rel


def comments(rel, text):
    """(line, text) of the comments of a code file; the whole of a doc."""
    ext = os.path.splitext(rel)[1]
    if ext == ".md":
        for n, line in enumerate(text.split("\n"), 1):
            yield n, line
        return
    if ext in (".c", ".h", ".cpp", ".cc"):
        pattern = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
    else:  # shell, Python, CMake: '#' to the end of the line
        pattern = re.compile(r'#[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'')
    for m in pattern.finditer(text):
        s = m.group(0)
        if s[0] in "\"'":
            continue
        start = text.count("\n", 0, m.start()) + 1
        for k, line in enumerate(s.split("\n")):
            yield start + k, line


def load_allow():
    allow = []
    path = os.path.join(ROOT, "tests", "lint", "words_allow.txt")
    if not os.path.exists(path):
        return allow
    for line in open(path, encoding="utf-8"):
        line = line.split("#", 1)[0].strip()
        if line:
            allow.append(line)
    return allow


def allowed(name, allow):
    return any(name == a or (a.endswith("/") and name.startswith(a)) for a in allow)


def exists(name):
    return os.path.exists(os.path.join(ROOT, name))


def bare_exists(name):
    """A file of that name anywhere in the tree, or a system header."""
    if name in BASENAMES:
        return True
    return name.endswith(".h") and (os.path.exists(os.path.join("/usr/include", name)) or any(
        os.path.exists(os.path.join("/usr/include", d, name)) for d in os.listdir("/usr/include")
        if os.path.isdir(os.path.join("/usr/include", d))))


def check_paths(rel, text, allow, out):
    for n, line in comments(rel, text):
        for m in PATH_RE.finditer(line):
            name = m.group(1).rstrip(".-")
            after = line[m.end():m.end() + 1]
            if after in ("*", "<", "{", "$", "[", "%") or "..." in name or "XXX" in name:
                continue  # a glob or a placeholder
            name = re.sub(r"[.]{2,}$", "", name)
            if allowed(name, allow) or exists(name) or exists(name + ".c"):
                continue  # a file, or a program built from NAME.c
            if PLACEHOLDER_RE.search(name):
                continue  # tests/golden/CASE, app/F/, run-runN.csv
            out.append("%s:%d: names %s, which does not exist" % (rel, n, name))
        for m in BARE_RE.finditer(line):
            name = m.group(1)
            if line[max(0, m.start() - 2):m.start()] == "](":
                continue  # a Markdown link's target, checked below
            if not (allowed(name, allow) or bare_exists(name) or PLACEHOLDER_RE.search(name)):
                out.append("%s:%d: names %s, which is no file of the repository" % (rel, n, name))
        if rel.endswith(".md"):
            for m in LINK_RE.finditer(line):
                target = m.group(1)
                if re.match(r"[a-z]+:", target) or target.startswith("/"):
                    continue
                name = os.path.normpath(os.path.join(os.path.dirname(rel), target))
                if name.startswith("..") or allowed(name, allow) or exists(name):
                    continue
                out.append("%s:%d: links to %s, which does not exist" % (rel, n, target))
    if rel.endswith((".c", ".h", ".cpp")):
        m = SELF_RE.match(text)
        if m and m.group(1) != os.path.basename(rel):
            out.append("%s:%d: opens as %s" % (rel, text.count("\n", 0, m.start(1)) + 1, m.group(1)))


def check_refs(rel, text, out):
    for n, line in comments(rel, text):
        if ISSUE_RE.search(line):
            out.append("%s:%d: cites an issue: %s" % (rel, n, ISSUE_RE.search(line).group(0)))
        if NOTES_RE.search(line):
            out.append("%s:%d: cites notes outside the repository: %s" % (rel, n, NOTES_RE.search(line).group(0)))


def findings(rule):
    allow = load_allow()
    out = []
    count = 0
    for rel in files():
        if rel.startswith(os.path.join("tests", "lint", "fixtures")):
            continue
        with open(os.path.join(ROOT, rel), encoding="utf-8", errors="replace") as f:
            text = f.read()
        count += 1
        if rule == "paths":
            check_paths(rel, text, allow, out)
        else:
            check_refs(rel, text, out)
    return out, count


def main():
    rule = sys.argv[1] if len(sys.argv) > 1 else ""
    if rule == "fixture":
        set_root(FIXTURE)
        got = findings("paths")[0] + findings("refs")[0]
        with open(os.path.join(FIXTURE, "expected.txt"), encoding="utf-8") as f:
            want = [line.rstrip("\n") for line in f if line.strip()]
        if sorted(got) != sorted(want):
            print("words.py fixture: found\n  %s\nexpected\n  %s" % ("\n  ".join(got), "\n  ".join(want)))
            return 1
        print("words.py fixture: ok (%d defects found, as expected)" % len(got))
        return 0
    if rule not in ("paths", "refs"):
        print("usage: words.py paths|refs|fixture", file=sys.stderr)
        return 2
    set_root(REPO)
    out, count = findings(rule)
    for line in out:
        print(line)
    if out:
        print("words.py %s: %d findings in %d files read" % (rule, len(out), count))
        return 1
    print("words.py %s: ok (%d files read)" % (rule, count))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Figure lint (docs/figures.md#figure-lint): checks what a figure's PDF shows as text.

  figure_lint.py [--waivers FILE] FILE...

FILE is a PDF (read with poppler's `pdftotext -bbox-layout`) or that command's output saved as
.html. Every word box is in PDF points at the figure's print size. Complaints, one per line as
`FILE: message`:
  overlap      two text boxes overlap (by more than 0.3 pt both ways)
  outside      a text box leaves the page
  small        text below 6 pt (box height over DejaVu Sans' ascent + descent, 1.164 em)
  tick format  an axis' tick labels with different decimals, or plain and exponent forms mixed
  no unit      an axis (a row or column of tick labels) with no label, or a label without a
               unit: "(unit)", "[unit]" ("(1)" when dimensionless), "q / unit", a scaled
               variable "t* = t / sqrt(D/g)" or a reduced quantity "E*_kin"
  series       the colour bars of a series (files named alike but for numbers: collapse_0.2s,
               collapse_0.5s; 7.12a, 7.12b) show different ticks
--waivers FILE: known defects, one a line `NAME-PATTERN<TAB>COMPLAINT-PREFIX  # why`
(fnmatch on the file's base name): complaints they match are printed as waived and do not
count; a waiver that matched nothing is reported as stale (not an error).
Exit status: 0 clean, 1 with complaints, 2 on a usage error or an unreadable file.
"""
import fnmatch
import html
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

EM = 1.1641  # DejaVu Sans: (ascent + descent) / em, the height of pdftotext's word boxes
MIN_PT = 6.0
OVERLAP_PT = 0.3  # boxes touching within this are not an overlap
ALIGN_PT = 0.35  # tick labels sharing a baseline or an edge
NUMBER = re.compile(r"^[-\u2212]?(\d+)(?:\.(\d+))?(?:[eE]([-+\u2212]?\d+))?$")


class Word:
    def __init__(self, x0, y0, x1, y1, text, line):
        self.x0, self.y0, self.x1, self.y1, self.text, self.line = x0, y0, x1, y1, text, line


def read_boxes(path):
    """The page size and the words (with their line number and whether it runs vertically)."""
    if path.endswith(".pdf"):
        run = subprocess.run(["pdftotext", "-bbox-layout", "-f", "1", "-l", "1", path, "-"],
                             capture_output=True, text=True)
        if run.returncode != 0:
            raise OSError("pdftotext failed: " + run.stderr.strip())
        source = run.stdout
    else:
        with open(path, encoding="utf-8") as f:
            source = f.read()
    # the <head> holds metadata with entities XML does not know; the <doc> part is plain
    start, end = source.find("<doc>"), source.find("</doc>")
    if start < 0 or end < 0:
        raise ValueError("no <doc> in pdftotext's output")
    doc = ET.fromstring(source[start:end + len("</doc>")])
    page = doc.find("page")
    width, height = float(page.get("width")), float(page.get("height"))
    words, vertical = [], []
    for number, line in enumerate(page.iter("line")):
        ws = []
        for w in line.iter("word"):
            ws.append(Word(float(w.get("xMin")), float(w.get("yMin")), float(w.get("xMax")),
                           float(w.get("yMax")), html.unescape(w.text or ""), number))
        # a line of several words stacked top to bottom is set vertically (a y axis' label)
        stacked = len(ws) > 1 and all(
            a.y0 >= b.y1 - OVERLAP_PT or b.y0 >= a.y1 - OVERLAP_PT
            for i, a in enumerate(ws) for b in ws[i + 1:])
        vertical.append(stacked)
        words.extend(ws)
    return width, height, words, vertical


def size_pt(word, vertical):
    return (word.x1 - word.x0 if vertical[word.line] else word.y1 - word.y0) / EM


def ink(w, vertical):
    """The box from the cap height (0.76 em above the baseline, where digits, capitals and
    parentheses end) to 0.14 em below it (the parentheses' foot), in place of the font's
    ascent (0.93 em) and descent (0.24 em): what a reader sees collide."""
    if vertical[w.line]:
        em = (w.x1 - w.x0) / EM
        return (w.x0 + 0.10 * em, w.y0, w.x1 - 0.17 * em, w.y1)
    em = (w.y1 - w.y0) / EM
    return (w.x0, w.y0 + 0.17 * em, w.x1, w.y1 - 0.10 * em)


def overlaps(a, b):
    return (min(a[2], b[2]) - max(a[0], b[0]) > OVERLAP_PT and
            min(a[3], b[3]) - max(a[1], b[1]) > OVERLAP_PT)


def evenly(run, along):
    """Distinct labels at even steps (within a quarter), as an axis' ticks are."""
    if len({w.text for w in run}) < len(run):
        return False
    steps = [along(b) - along(a) for a, b in zip(run, run[1:])]
    return min(steps) > 0 and max(steps) <= 1.25 * min(steps)


def in_list(group, words):
    """A column of numbers that goes on, at the same left edge and step, with lines
    that are not numbers alone (a legend's entries "0.5 wide", "0.75 narrow", "1.0", "1.5") is
    a list, not a colour bar's ticks."""
    step = (group[-1].y0 - group[0].y0) / (len(group) - 1)
    members = {id(w) for w in group}
    for w in words:
        if id(w) in members or OFFSET.match(w.text) or abs(w.x0 - group[0].x0) > ALIGN_PT:
            continue
        for end, sign in ((group[0], -1), (group[-1], 1)):
            if abs(w.y0 - (end.y0 + sign * step)) <= 0.25 * step:
                return True
    return False


def tick_groups(words, vertical):
    """Rows (x axes) and columns (y axes, colour bars) of at least two numeric labels, on lines
    of numbers only (a number inside a time stamp or a legend is no tick; pdftotext may join
    close x tick labels into one line)."""
    other = {w.line for w in words if not NUMBER.match(w.text)}
    numbers = [w for w in words
               if NUMBER.match(w.text) and not vertical[w.line] and w.line not in other]
    rows, cols = [], []

    def cluster(key, along, into):
        done = set()
        for w in numbers:
            if id(w) in done:
                continue
            same = sorted((v for v in numbers if abs(key(v) - key(w)) <= ALIGN_PT), key=along)
            done.update(id(v) for v in same)
            # split where the step between neighbours jumps (two panels side by side)
            run = [same[0]]
            for v in same[1:] + [None]:
                if v is None or (len(run) > 1 and
                                 along(v) - along(run[-1]) > 1.6 * (along(run[-1]) - along(run[-2]))):
                    if len(run) > 1 and evenly(run, along):
                        into.append(run)
                    run = []
                if v is not None:
                    run.append(v)

    cluster(lambda w: w.y1, lambda w: w.x0, rows)  # rows: one baseline
    cluster(lambda w: w.x1, lambda w: w.y0, cols)  # columns: right-aligned (y axes)
    cluster(lambda w: w.x0, lambda w: w.y0, cols)  # columns: left-aligned (colour bars)
    cols = [g for g in cols if not in_list(g, words)]
    # a label in a row of three or more is an x tick, not a column's (the first x tick of one
    # panel may share its left edge with a y tick of the panel above)
    in_rows = {id(w) for r in rows if len(r) > 2 for w in r}
    cols = [c for c in ([w for w in g if id(w) not in in_rows] for g in cols)
            if len(c) > 1 and evenly(c, lambda w: w.y0)]
    unique = []
    cols.sort(key=len, reverse=True)
    for g in cols:  # a column aligned on both edges is found twice, or in parts
        if not any({id(w) for w in g} <= {id(w) for w in u} for u in unique):
            unique.append(g)
    # a label in a column is a y tick or a colour bar's: the lowest tick of a y axis and of a
    # colour bar beside it share a baseline and would otherwise read as an x axis' row
    in_cols = {id(w) for g in unique for w in g}
    rows = [r for r in ([w for w in run if id(w) not in in_cols] for run in rows)
            if len(r) > 1 and evenly(r, lambda w: w.x0)]
    return rows, unique


def tick_format(group):
    forms = set()
    for w in group:
        m = NUMBER.match(w.text)
        forms.add(("e" if m.group(3) is not None else "f", len(m.group(2) or "")))
    return forms


# a unit in brackets, "q / unit", a scaled variable "t* = t / sqrt(D/g)" or a reduced (starred,
# dimensionless) quantity "E*_kin"
OFFSET = re.compile("^\u00d710\\S*$")
HAS_UNIT = re.compile(r"\(.+\)\s*$|\[.+\]\s*$|\s/\s|=|\*")


def axis_label(group, is_row, words, vertical):
    """The text of the line nearest the group on its outer side (below a row, beside a column)."""
    x0, x1 = min(w.x0 for w in group), max(w.x1 for w in group)
    y0, y1 = min(w.y0 for w in group), max(w.y1 for w in group)
    fs = max(w.y1 - w.y0 for w in group)
    best, best_gap = None, None
    for w in words:
        if w in group or OFFSET.match(w.text):  # an axis' offset "×10⁴" is not its label
            continue
        if is_row:
            gap = w.y0 - y1
            near = not vertical[w.line] and min(w.x1, x1) > max(w.x0, x0) and -0.3 * fs < gap < 2.5 * fs
        else:
            gap = x0 - w.x1 if w.x1 <= x0 + 0.5 else w.x0 - x1
            near = vertical[w.line] and min(w.y1, y1) > max(w.y0, y0) and -0.3 * fs < gap < 3.0 * fs
        if near and (best_gap is None or gap < best_gap):
            best, best_gap = w, gap
    if best is None:
        return None
    line = [w for w in words if w.line == best.line]
    line.sort(key=(lambda w: -w.y1) if vertical[best.line] else (lambda w: w.x0))
    return " ".join(w.text for w in line)


def lint(path, colour_bars):
    width, height, words, vertical = read_boxes(path)
    out = []
    boxes = [ink(w, vertical) for w in words]
    for i, a in enumerate(words):
        for j in range(i + 1, len(words)):
            b = words[j]
            if overlaps(boxes[i], boxes[j]):
                out.append("overlap: '%s' and '%s' at (%.1f, %.1f) pt" % (a.text, b.text, a.x0, a.y0))
    for w in words:
        if w.x0 < -0.01 or w.y0 < -0.01 or w.x1 > width + 0.01 or w.y1 > height + 0.01:
            out.append("outside: '%s' leaves the %.1f x %.1f pt page" % (w.text, width, height))
        pt = size_pt(w, vertical)
        if pt < MIN_PT - 0.05:
            out.append("small: '%s' is %.1f pt (at least %.0f pt)" % (w.text, pt, MIN_PT))
    rows, cols = tick_groups(words, vertical)
    for group, is_row in [(g, True) for g in rows] + [(g, False) for g in cols]:
        texts = ", ".join(w.text for w in group)
        axis = "x" if is_row else "y"
        if len(tick_format(group)) > 1:
            out.append("tick format: the %s axis' ticks %s mix formats" % (axis, texts))
        label = axis_label(group, is_row, words, vertical)
        if label is None:
            out.append("no unit: the %s axis with ticks %s has no label" % (axis, texts))
        elif not HAS_UNIT.search(label):
            out.append("no unit: the %s axis' label '%s' has no unit" % (axis, label))
        if not is_row and min(w.x0 for w in group) > 0.5 * width:
            colour_bars.append(tuple(w.text for w in group))
    return out


def series_of(path):
    """Files of one series share this key: the name with numbers (and a panel letter) blanked."""
    name = os.path.basename(path)
    return os.path.join(os.path.dirname(path), re.sub(r"\d+(\.\d+)*[a-z]?s?", "#", name))


def read_waivers(path):
    waivers = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].rstrip()
            if not line:
                continue
            if "\t" not in line:
                raise ValueError("%s:%d: expected NAME-PATTERN<TAB>COMPLAINT-PREFIX" % (path, number))
            name, prefix = line.split("\t", 1)
            waivers.append([name.strip(), prefix.strip(), 0])
    return waivers


def main(argv):
    args = argv[1:]
    if not args or args[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if args else 2
    waivers = []
    if args[0] == "--waivers":
        try:
            waivers = read_waivers(args[1])
        except (IndexError, OSError, ValueError) as e:
            print("figure_lint: %s" % e, file=sys.stderr)
            return 2
        args = args[2:]
    status = 0
    series = {}

    def complain(path, text):
        for w in waivers:
            if fnmatch.fnmatch(os.path.basename(path), w[0]) and text.startswith(w[1]):
                w[2] += 1
                print("%s: waived: %s" % (path, text))
                return 0
        print("%s: %s" % (path, text))
        return 1

    for path in args:
        bars = []
        try:
            complaints = lint(path, bars)
        except (OSError, ValueError, ET.ParseError) as e:
            print("%s: cannot read: %s" % (path, e), file=sys.stderr)
            return 2
        series.setdefault(series_of(path), []).append((path, bars))
        for c in complaints:
            status |= complain(path, c)
    for members in series.values():
        if len(members) < 2:
            continue
        first_path, first = members[0]
        for path, bars in members[1:]:
            if bars != first:
                status |= complain(path, "series: colour bar %s, but %s has %s" %
                                   (list(bars), os.path.basename(first_path), list(first)))
    for w in waivers:
        if w[2] == 0:
            print("figure_lint: stale waiver (nothing matched): %s\t%s" % (w[0], w[1]))
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""cli_docs.py SABLIER CLI_MD MAN_PAGE: docs/cli.md and the man page against the program.

- every command that `sablier --help` lists has a section "## `sablier COMMAND`" in docs/cli.md
  whose option table (the first cell of each row) names exactly the options that
  `sablier COMMAND --help` names: an option missing from either side fails;
- the man page names every option of every command's --help (as tests/install/check.sh does for
  an installed copy);
- one list of exit statuses: the statuses of `sablier --help`'s "exit status:" paragraph, of the
  man page's EXIT STATUS section, of docs/cli.md's opening paragraph and of the header of its
  exit-status table are the same; each command's --help "exit status:" paragraph gives exactly
  the statuses of its row in that table; and the man page's entries for 3 and 130/143 name
  exactly the commands whose rows have them.
"""
import re
import subprocess
import sys

OPTION = re.compile(r"(?:^|[\s\[(,|])(--?[A-Za-z][A-Za-z0-9-]*)")
problems = []


def fail(message):
    problems.append(message)


def helptext(sablier, *args):
    done = subprocess.run([sablier, *args], capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"`sablier {' '.join(args)}` exits {done.returncode}")
    return done.stdout


def options_of(text):
    return {m for m in OPTION.findall(text) if m not in ("-h", "--help")}


def exit_paragraph(text):
    """The statuses of the paragraph that starts with "exit status:" (None when there is none)."""
    m = re.search(r"^exit status:(.*?)(?:\n\s*\n|\Z)", text, re.S | re.M)
    if not m:
        return None
    body = " " + " ".join(m.group(1).split())
    statuses = set()
    for item in re.findall(r"(?:^|[:,])\s*(\d+(?:/\d+)*) ", body):
        statuses.update(int(n) for n in item.split("/"))
    return statuses


def sections(markdown):
    """docs/cli.md's "## `sablier NAME`" sections: {NAME: text}."""
    out = {}
    parts = re.split(r"^## ", markdown, flags=re.M)
    for part in parts[1:]:
        m = re.match(r"`sablier ([a-z]+)`", part)
        if m:
            out[m.group(1)] = part
    return out


def table_options(section):
    """The options named in the first cell of the section's table rows."""
    found = set()
    for line in section.splitlines():
        if line.startswith("| `-"):
            found |= options_of(line.split("|")[1].replace("`", " "))
    return found


def exit_table(markdown):
    """docs/cli.md's exit-status table: (header statuses, {command: statuses})."""
    lines = markdown.splitlines()
    for i, line in enumerate(lines):
        if line.startswith("| command | 0 |"):
            head = [c.strip() for c in line.strip().strip("|").split("|")]
            columns = [[int(n) for n in re.findall(r"\d+", c)] for c in head[1:]]
            rows = {}
            for row in lines[i + 2:]:
                if not row.startswith("|"):
                    break
                cells = [c.strip() for c in row.strip().strip("|").split("|")]
                have = set()
                for cell, statuses in zip(cells[1:], columns):
                    if not cell.startswith("-"):
                        have.update(statuses)
                for name in re.findall(r"`([a-z]+)`", cells[0]):
                    rows[name] = have
            return {n for c in columns for n in c}, rows
    fail("docs/cli.md: no exit-status table (a row `| command | 0 | ...`)")
    return set(), {}


def man_exit(man):
    """The man page's EXIT STATUS section: (statuses, {status: commands named in its entry})."""
    m = re.search(r"^\.SH EXIT STATUS\n(.*?)(?=^\.SH )", man, re.S | re.M)
    if not m:
        fail("man page: no EXIT STATUS section")
        return set(), {}
    entries = re.split(r"^\.TP\n", m.group(1), flags=re.M)[1:]
    statuses, named = set(), {}
    for entry in entries:
        head, _, body = entry.partition("\n")
        numbers = [int(n) for n in re.findall(r"\d+", head)]
        commands = set(re.findall(r"^\.(?:BR?|RB) (?:\( )?([a-z]+)\b", body, re.M))
        for n in numbers:
            statuses.add(n)
            named[n] = commands
    return statuses, named


def main():
    sablier, cli_path, man_path = sys.argv[1:4]
    markdown = open(cli_path, encoding="utf-8").read()
    man = open(man_path, encoding="utf-8").read()
    top = helptext(sablier, "--help")
    listed = top.split("commands:", 1)[-1].split("\n\n", 1)[0]
    commands = re.findall(r"^  ([a-z]+) [A-Z]", listed, re.M)
    if len(commands) < 5:
        fail(f"sablier --help lists too few commands: {commands}")
    docs = sections(markdown)
    header, rows = exit_table(markdown)
    for command in commands:
        text = helptext(sablier, command, "--help")
        said = options_of(text)
        if command not in docs:
            fail(f"docs/cli.md: no section \"## `sablier {command}`\"")
        else:
            documented = table_options(docs[command])
            for o in sorted(said - documented):
                fail(f"docs/cli.md: `sablier {command}`'s option table lacks {o} (in --help)")
            for o in sorted(documented - said):
                fail(f"`sablier {command} --help` lacks {o} (in docs/cli.md's table)")
        for o in sorted(said):
            if o.replace("-", "\\-") not in man:
                fail(f"man page: does not mention `{command}`'s option {o}")
        statuses = exit_paragraph(text)
        if statuses is None:
            fail(f"`sablier {command} --help` has no \"exit status:\" paragraph")
        elif command not in rows:
            fail(f"docs/cli.md: the exit-status table has no row for `{command}`")
        elif statuses != rows[command]:
            fail(f"exit statuses of `{command}`: --help says {sorted(statuses)}, docs/cli.md "
                 f"says {sorted(rows[command])}")
    overall = exit_paragraph(top) or set()
    intro = re.search(r"^Exit status, for every command\b(.*?)\n\n", markdown, re.S | re.M)
    intro_statuses = {int(n) for n in re.findall(r"\*\*(\d+)\*\*", intro.group(1))} if intro else set()
    man_statuses, man_named = man_exit(man)
    lists = {"sablier --help": overall, "the man page": man_statuses,
             "docs/cli.md's opening paragraph": intro_statuses,
             "docs/cli.md's exit-status table": header,
             "the commands' --help": set().union(*rows.values()) if rows else set()}
    for name, found in lists.items():
        if found != overall or not found:
            fail(f"exit statuses: {name} says {sorted(found)}, sablier --help {sorted(overall)}")
    for status in (3, 130, 143):
        expect = {c for c, s in rows.items() if status in s}
        if man_named.get(status, set()) != expect:
            fail(f"man page: the entry for exit status {status} names "
                 f"{sorted(man_named.get(status, set()))}, docs/cli.md's table {sorted(expect)}")
    for p in problems:
        print("cli_docs:", p, file=sys.stderr)
    if problems:
        return 1
    print(f"cli_docs: {len(commands)} commands: options and exit statuses agree "
          f"(statuses {sorted(overall)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

# SPDX-License-Identifier: MIT
"""Writes a C program that prints sizeof and offsetof of every struct mirrored in
sablier/_capi.py, compiles it against the source tree's headers, and returns both tables."""
import ctypes
import os
import shutil
import subprocess


def _fields(ctype):
    return [f[0] for f in ctype._fields_]


def c_source(structs):
    lines = ["#include <stddef.h>", "#include <stdio.h>"]
    headers = sorted({h for h, _ in structs.values()})
    lines += ['#include "%s"' % h for h in headers]
    lines.append("int main(void) {")
    for name, (_, ctype) in sorted(structs.items()):
        lines.append('    printf("%s %%zu\\n", sizeof(%s));' % (name, name))
        for f in _fields(ctype):
            lines.append('    printf("%s.%s %%zu\\n", offsetof(%s, %s));' % (name, f, name, f))
    lines.append("    return 0;\n}")
    return "\n".join(lines) + "\n"


def python_table(structs):
    out = {}
    for name, (_, ctype) in structs.items():
        out[name] = ctypes.sizeof(ctype)
        for f in _fields(ctype):
            out[name + "." + f] = getattr(ctype, f).offset
    return out


def compiler():
    for cc in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if cc and shutil.which(cc):
            return shutil.which(cc)
    return None


def c_table(structs, source_dir, workdir):
    cc = compiler()
    if cc is None:
        return None
    src = os.path.join(workdir, "abi_probe.c")
    exe = os.path.join(workdir, "abi_probe")
    with open(src, "w") as f:
        f.write(c_source(structs))
    subprocess.run([cc, "-std=c17", "-I", source_dir, "-I", os.path.join(source_dir, "app"),
                    src, "-o", exe], check=True, capture_output=True, text=True)
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout
    table = {}
    for line in out.splitlines():
        k, v = line.split()
        table[k] = int(v)
    return table

#!/usr/bin/env python3
"""reference/gpu/bundle_libs.py — copies the shared libraries an executable needs into a folder,
for a machine that lacks them (docs/reference.md, "On a real GPU"), replacing the heavy ones the
reference tests never call by stubs.

Debian's OpenImageIO links OpenCV, FFmpeg, DCMTK, libheif, OpenVDB, LibRaw and OpenColorIO, and
through them GDAL, GStreamer, ICU and ~250 libraries (~350 MiB). The reference tests only read
JPEG/PNG and write EXR/PNG, so those libraries are loaded but never called. A stub has the same
SONAME and exports, with the same version, every dynamic symbol of the original that the
executable or a copied library imports (functions abort with a message, except default
constructors and destructors, which static initialisers call and which do nothing; data objects
are zero-filled with the original size), so BIND_NOW relocations resolve, and it needs nothing but
libc. If a stubbed function is ever called, the process aborts
with "aquarelle GPU bundle: a stubbed library function was called" (never silently wrong).

Usage: bundle_libs.py EXECUTABLE LIBDIR CXXDIR
  LIBDIR  receives the libraries and stubs; CXXDIR receives libstdc++/libgcc_s (used only where
  the target machine has none). glibc's core libraries and the GL/EGL libraries (which must come
  from the target's GPU driver through GLVND) are left out.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

EXCLUDE = re.compile(r"^(libc|libm|libpthread|libdl|librt|ld-linux[-\w]*|libEGL|libGL|libGLX|libGLdispatch|libOpenGL)\.so")
CXX = re.compile(r"^(libstdc\+\+|libgcc_s)\.so")
# Loaded by OpenImageIO's format plugins and colour management, never called by tests/reference.
STUB = re.compile(
    r"^(libopencv_\w+|libavcodec|libavformat|libavutil|libswscale|libswresample|libdcm\w+|liboflog|libofstd|"
    r"libheif|libopenvdb|libraw_r|libOpenColorIO)\.so")

# Run by OpenImageIO's static initialisers and at exit (DCMTK's `static DiRegister`, ...): default
# constructors and destructors are no-ops in a stub; everything else aborts.
NOOP = re.compile(r"(C[12]Ev|D[012]Ev)$|^_ZN5OFLog9configure")
# Version queries (OpenImageIO's plugin catalogue asks each format library for its version):
# return a pointer to the string "stub" (as an integer: an arbitrary value).
VERSION = re.compile(r"version", re.IGNORECASE)


def needed(path):
    out = subprocess.run(["readelf", "-dW", path], capture_output=True, text=True, check=True).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)


def ldd_map(exe):
    out = subprocess.run(["ldd", exe], capture_output=True, text=True, check=True).stdout
    m = {}
    for line in out.splitlines():
        g = re.match(r"\s*(\S+) => (/\S+)", line)
        if g:
            m[g.group(1)] = g.group(2)
    return m


def undefined(path):
    """Names of the dynamic symbols `path` imports."""
    out = subprocess.run(["readelf", "--dyn-syms", "-W", path], capture_output=True, text=True, check=True).stdout
    names = set()
    for line in out.splitlines():
        f = line.split()
        if len(f) >= 8 and f[0].rstrip(":").isdigit() and f[6] == "UND":
            names.add(f[7].split("@", 1)[0])
    return names


def make_stub(src, soname, dst, wanted):
    out = subprocess.run(["readelf", "--dyn-syms", "-W", src], capture_output=True, text=True, check=True).stdout
    asm = ['\t.section .note.GNU-stack,"",@progbits', "\t.section .rodata", "aq_stub_version:", '\t.asciz "stub"',
           '\t.text', '\t.hidden aq_stub_fail']
    nodes = {}  # version -> [default-version names]
    plain = []
    n = 0
    for line in out.splitlines():
        f = line.split()
        if len(f) < 8 or not f[0].rstrip(":").isdigit():
            continue
        size, typ, bind, ndx, name = f[2], f[3], f[4], f[6], f[7]
        if ndx in ("UND", "ABS") or bind not in ("GLOBAL", "WEAK", "GNU_UNIQUE"):
            continue
        ver, default = None, True
        if "@@" in name:
            name, ver = name.split("@@", 1)
        elif "@" in name:
            name, ver = name.split("@", 1)
            default = False
        ver = ver.split()[0] if ver else None
        if name in ("_init", "_fini", "_edata", "_end", "__bss_start") or name not in wanted:
            continue
        sz = int(size, 0) if size.startswith("0x") else int(size)
        n += 1
        label = f'"{name}"' if default else f"aq_stub_alias_{n}"
        directive = ".weak" if bind == "WEAK" else ".globl"  # aliases of non-default versions: global too
        if typ in ("OBJECT", "TLS", "COMMON"):
            section = '.section .tbss,"awT",@nobits' if typ == "TLS" else ".bss"
            asm += [f"\t{section}", f"\t{directive} {label}", f"\t.type {label}, @object",
                    f"\t.size {label}, {sz}", "\t.balign 16", f"{label}:", f"\t.zero {max(sz, 1)}", "\t.text"]
        elif NOOP.search(name):
            asm += [f"\t{directive} {label}", f"\t.type {label}, @function", f"{label}:", "\tret"]
        elif VERSION.search(name):
            asm += [f"\t{directive} {label}", f"\t.type {label}, @function", f"{label}:",
                    "\tlea aq_stub_version(%rip), %rax", "\tret"]
        else:  # FUNC, IFUNC, NOTYPE
            asm += [f"\t{directive} {label}", f"\t.type {label}, @function", f"{label}:",
                    f"\tlea .Laq_name_{n}(%rip), %rdi", "\tjmp aq_stub_fail",
                    "\t.section .rodata", f".Laq_name_{n}:", f'\t.asciz "{name}"', "\t.text"]
        if not default:
            asm.append(f'\t.symver {label}, "{name}"@{ver}')
        if ver:
            nodes.setdefault(ver, [])
            if default:
                nodes[ver].append(name)
        else:
            plain.append(name)
    with tempfile.TemporaryDirectory() as d:
        s = os.path.join(d, "stub.s")
        c = os.path.join(d, "fail.c")
        with open(s, "w") as fh:
            fh.write("\n".join(x for x in asm if x) + "\n")
        with open(c, "w") as fh:
            fh.write('#include <stdlib.h>\n#include <string.h>\n#include <unistd.h>\n__attribute__((visibility("hidden"))) void aq_stub_fail(const char* name) {'
                     ' static const char m[] = "aquarelle GPU bundle: a stubbed library function was called (' + soname +
                     '): "; write(2, m, sizeof m - 1); write(2, name, strlen(name)); write(2, "\\n", 1); abort(); }\n')
        cmd = ["gcc", "-shared", "-fPIC", "-o", dst, s, c, f"-Wl,-soname,{soname}", "-Wl,-z,now"]
        if nodes:
            vs = os.path.join(d, "stub.map")
            with open(vs, "w") as fh:
                vers = list(nodes)
                for i, v in enumerate(vers):
                    names = nodes[v] + (plain if i == 0 else [])
                    body = "".join(f' "{x}";' for x in names)
                    fh.write(f"{v} {{ global:{body} }};\n" if body else f"{v} {{ }};\n")
            cmd.append(f"-Wl,--version-script={vs}")
        subprocess.run(cmd, check=True)


def main():
    exe, libdir, cxxdir = sys.argv[1:4]
    os.makedirs(libdir, exist_ok=True)
    os.makedirs(cxxdir, exist_ok=True)
    where = ldd_map(exe)
    todo, seen, stubbed, copied = list(needed(exe)), set(), [], []
    while todo:
        name = todo.pop()
        if name in seen or EXCLUDE.match(name):
            continue
        seen.add(name)
        path = where.get(name)
        if not path:
            sys.exit(f"bundle_libs: {name} not resolved by ldd {exe}")
        if CXX.match(name):
            shutil.copy(path, os.path.join(cxxdir, name))
        elif STUB.match(name):
            stubbed.append(name)
        else:
            shutil.copy(path, os.path.join(libdir, name))
            copied.append(name)
            todo += needed(path)
    # A stub exports only what the executable and the copied libraries import (BIND_NOW resolves
    # exactly those); the stubbed libraries import nothing from each other, being stubs.
    wanted = set().union(undefined(exe), *(undefined(os.path.join(libdir, c)) for c in copied))
    for name in stubbed:
        make_stub(where[name], name, os.path.join(libdir, name), wanted)
    print(f"copied {len(copied)} libraries, stubbed {len(stubbed)}: {' '.join(sorted(stubbed))}")


if __name__ == "__main__":
    main()

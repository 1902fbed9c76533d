#!/usr/bin/python3
"""tests/layering_check.py — the layers include only downwards (docs/architecture.md "Layers"):
core includes no other module; scenes includes core; raster includes core and scenes; stylize
includes core, scenes and raster; app and python include anything but each other's executables.
Checks every #include "..." of the project's sources. Also: app/ and python/ name no stage (a
string literal equal to a registered stage's name, `v.stage = "..."` in stylize/): what a stage
needs from the job is declared by the stage (docs/stylize.md "Scene inputs").
Usage: layering_check.py SOURCE_DIR."""
import os
import re
import sys

ALLOWED = {
    "core": {"core"},
    "scenes": {"core", "scenes"},
    "raster": {"core", "scenes", "raster"},
    "stylize": {"core", "scenes", "raster", "stylize"},
}
root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
include = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/')
bad = []


def lines_of(layer, exts=(".h", ".cpp")):
    """(path, line number, line) of every source file of a layer."""
    for dirpath, _, files in os.walk(os.path.join(root, layer)):
        for f in sorted(files):
            if f.endswith(exts):
                path = os.path.join(dirpath, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    for n, line in enumerate(fh, 1):
                        yield os.path.relpath(path, root), n, line


for layer, allowed in ALLOWED.items():
    for path, n, line in lines_of(layer):
        m = include.match(line)
        if m and m.group(1) not in allowed and os.path.isdir(os.path.join(root, m.group(1))):
            bad.append("%s:%d: %s includes %s/ (%s may include only %s)" % (
                path, n, layer, m.group(1), layer, ", ".join(sorted(allowed))))
stage_decl = re.compile(r'\.stage\s*=\s*"([a-z_0-9]+)"')
stages = {name for _, _, line in lines_of("stylize", (".cpp",)) for name in stage_decl.findall(line)}
if len(stages) < 10:
    bad.append("found only %d stage declarations in stylize/ (expected every built-in stage)" % len(stages))
literal = re.compile(r'"([a-z_0-9]+)"')
for layer in ("app", "python"):
    for path, n, line in lines_of(layer):
        for name in literal.findall(line.split("//")[0]):
            if name in stages:
                bad.append("%s:%d: names the stage \"%s\" (declare what the stage needs in its "
                           "StageVariant instead)" % (path, n, name))
for b in bad:
    print(b)
print("layering: %s" % ("%d finding(s) against the layers" % len(bad) if bad else "every include goes downwards; app/ and python/ name no stage"))
sys.exit(1 if bad else 0)

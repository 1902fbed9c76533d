#!/usr/bin/env python3
"""Checks that the docs name files that exist and that no log word slipped in.

Usage: python3 tests/docs_check.py SOURCE_DIR

1. Every backquoted repository path of the form `dir/file.ext` in docs/*.md and README.md
   (dir one of the top-level source folders below; inline code spans and fenced code blocks, every
   whitespace-separated word of them) must exist under SOURCE_DIR. A trailing `:line` (or
   `:anything`) is stripped; a function name after a space is a separate word and not a path.
   Paths with placeholders (`<`, `*`, `#`, `{`, `$`, or an all-capitals word such as STAGE or NAME
   when the path does not exist) are skipped, as are paths under ../shared and build/.
2. The word "session" (any case) must not appear in docs/*.md, README.md or in the sources
   (*.h, *.cpp, *.py, *.js, *.html) under core/ scenes/ raster/ stylize/ app/ python/: the docs say
   what is true now; history belongs in git.

3. The example of docs/stylize.md "Writing a stage" (its first ```cpp block) is the code between
   the BEGIN and END lines of tests/stylize/writing_a_stage_test.cpp, which builds and tests it.

Exit 0 when everything holds, 1 with one line per problem otherwise (standard library only).
"""

import os
import re
import sys

PATH_DIRS = ("core", "scenes", "raster", "stylize", "reference", "app", "bench", "tests",
             "scripts", "python", "fuzz", "docs", "examples")
SOURCE_DIRS = ("core", "scenes", "raster", "stylize", "app", "python")
SOURCE_EXTS = (".h", ".cpp", ".py", ".js", ".html")
SKIP_DIR_NAMES = {"node_modules", "__pycache__", ".git"}

# A path starts at a word boundary that is not part of a longer path (so build/tests/x and
# ../shared/tests/x are not read as tests/x) and ends in a file name with an extension.
PATH_RE = re.compile(r"(?<![\w./~-])((?:%s)/[^\s`'\"(),;]*[^\s`'\"(),;:.])" % "|".join(PATH_DIRS))
FILE_RE = re.compile(r"^[^\s]*/[^/\s]*\.[A-Za-z0-9_]+$")
PLACEHOLDER_CHARS = set("<>*#{}$")
CAPS_WORD_RE = re.compile(r"(?<![A-Za-z])[A-Z][A-Z_]+(?![a-z])")
FENCE_RE = re.compile(r"^(```|~~~).*?^\1[ \t]*$", re.M | re.S)
INLINE_RE = re.compile(r"`([^`]+)`")
SESSION_RE = re.compile(r"\bsession", re.I)  # session, sessions; not possession


def code_spans(text):
    """Yields (line number, code text) of every fenced block and inline code span."""
    for m in FENCE_RE.finditer(text):
        yield text.count("\n", 0, m.start()) + 1, m.group(0)
    # The prose with every fenced block blanked to its line breaks: the same line numbers.
    prose = FENCE_RE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    for m in INLINE_RE.finditer(prose):
        yield prose.count("\n", 0, m.start(1)) + 1, m.group(1)


def candidate_paths(code):
    for m in PATH_RE.finditer(code):
        path = m.group(1)
        path = path.split(":", 1)[0]  # `file.cpp:120`, `file.h:function`
        path = path.rstrip(".")
        if not FILE_RE.match(path):
            continue  # a folder or a benchmark name, not `dir/file.ext`
        yield path


def is_placeholder(path):
    return any(c in PLACEHOLDER_CHARS for c in path) or CAPS_WORD_RE.search(path) is not None


def check_paths(root, md_files):
    problems = []
    for md in md_files:
        with open(os.path.join(root, md), encoding="utf-8") as f:
            text = f.read()
        found = set()
        for line, code in code_spans(text):
            for path in candidate_paths(code):
                if os.path.exists(os.path.join(root, path)) or is_placeholder(path):
                    continue
                found.add((line, path))
        problems += ["%s:%d: `%s` does not exist" % (md, line, path) for line, path in sorted(found)]
    return problems


def check_session(root, files):
    problems = []
    for rel in files:
        try:
            with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
                for n, line in enumerate(f, 1):
                    if SESSION_RE.search(line):
                        problems.append("%s:%d: the word \"session\": %s" % (rel, n, line.strip()))
        except OSError as e:
            problems.append("%s: cannot read (%s)" % (rel, e))
    return problems


def check_stage_example(root):
    """The doc's example and the test's copy are the same text."""
    doc_path = os.path.join(root, "docs", "stylize.md")
    test_path = os.path.join(root, "tests", "stylize", "writing_a_stage_test.cpp")
    marker = '// %s docs/stylize.md "Writing a stage"\n'
    try:
        with open(doc_path, encoding="utf-8") as f:
            doc = f.read()
        with open(test_path, encoding="utf-8") as f:
            test = f.read()
    except OSError as e:
        return ["stage example: cannot read (%s)" % e]
    section = doc.find("## Writing a stage")
    block = re.search(r"```cpp\n(.*?)```", doc[section:], re.S) if section >= 0 else None
    begin, end = test.find(marker % "BEGIN"), test.find(marker % "END")
    if not block or begin < 0 or end < begin:
        return ["stage example: no ```cpp block under \"## Writing a stage\" in docs/stylize.md or no "
                "BEGIN/END lines in tests/stylize/writing_a_stage_test.cpp"]
    if block.group(1) != test[begin + len(marker % "BEGIN"):end]:
        return ["docs/stylize.md \"Writing a stage\": the example differs from the one "
                "tests/stylize/writing_a_stage_test.cpp builds"]
    return []


def main(argv):
    if len(argv) != 2:
        print("usage: docs_check.py SOURCE_DIR", file=sys.stderr)
        return 2
    root = argv[1]
    docs_dir = os.path.join(root, "docs")
    md_files = sorted("docs/" + name for name in os.listdir(docs_dir) if name.endswith(".md"))
    if os.path.exists(os.path.join(root, "README.md")):
        md_files.append("README.md")

    sources = []
    for top in SOURCE_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(d for d in dirnames if d not in SKIP_DIR_NAMES)
            for name in sorted(filenames):
                if name.endswith(SOURCE_EXTS):
                    sources.append(os.path.relpath(os.path.join(dirpath, name), root))

    problems = check_paths(root, md_files) + check_session(root, md_files + sources) + check_stage_example(root)
    for p in problems:
        print(p)
    if problems:
        print("docs_check: %d problem(s) in %d docs and %d sources" %
              (len(problems), len(md_files), len(sources)))
        return 1
    print("docs_check: %d docs and %d sources checked, every named path exists, no \"session\""
          % (len(md_files), len(sources)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

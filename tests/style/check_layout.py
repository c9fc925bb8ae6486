"""The house rules a newcomer can rely on (docs/architecture.md, issue 34), checked on the
tracked files of the source tree:

- every line of code, script and build file is at most 100 characters;
- no product file (apps/, dem/, shared/, continuum/) is longer than 500 lines;
- no C++ function in the product is longer than 100 lines (from its signature to its closing
  brace; a function is a definition that starts at column 0 and opens a brace).

Exit 0 when all hold; otherwise each offender is printed with its file and line, exit 1.
Usage: check_layout.py SOURCE_DIR
"""
import os
import re
import subprocess
import sys

MAX_LINE, MAX_FILE, MAX_FUNCTION = 100, 500, 100
PRODUCT = ("apps/", "dem/", "shared/", "continuum/")
CODE_DIRS = PRODUCT + ("tests/", "bench/", "python/", "studies/", "scripts/")
CODE_EXT = (".cc", ".h", ".py", ".sh", ".cmake")


def tracked(root):
    """The files git tracks, or every file under root outside build folders without git."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True,
                             check=True).stdout
        return [f for f in out.split("\n") if f]
    except (OSError, subprocess.CalledProcessError):
        found = []
        for d, dirs, files in os.walk(root):
            dirs[:] = [x for x in dirs if not x.startswith((".", "build", "out", "runs"))]
            found += [os.path.relpath(os.path.join(d, f), root) for f in files]
        return found


def is_code(path):
    if not path.startswith(CODE_DIRS) or "/corpus/" in path or "/fuzz/grown/" in path:
        return False
    return path.endswith(CODE_EXT) or path.endswith("CMakeLists.txt")


def function_lengths(lines):
    """(first line, length, name) of each function defined at column 0."""
    found, i = [], 0
    while i < len(lines):
        line = lines[i]
        starts = (line and not line[0].isspace() and "(" in line
                  and not line.startswith(("#", "//", "namespace", "struct", "class", "enum",
                                           "}", "using", "template"))
                  and not line.rstrip().endswith(";"))
        if not starts:
            i += 1
            continue
        j = i
        while j < len(lines) and not lines[j].rstrip().endswith(("{", ";")):
            j += 1
        if j == len(lines) or not lines[j].rstrip().endswith("{"):
            i += 1
            continue
        depth, k = 0, j
        for k in range(j, len(lines)):
            depth += lines[k].count("{") - lines[k].count("}")
            if depth <= 0:
                break
        name = re.search(r"([\w:~]+)\s*\(", line)
        found.append((i + 1, k - i + 1, name.group(1) if name else line.strip()[:40]))
        i = k + 1
    return found


def main(root):
    problems = []
    for path in tracked(root):
        if not is_code(path):
            continue
        with open(f"{root}/{path}", encoding="utf-8", errors="replace") as f:
            lines = f.read().split("\n")
        for n, line in enumerate(lines, 1):
            if len(line) > MAX_LINE:
                problems.append(f"{path}:{n}: line of {len(line)} characters (at most {MAX_LINE})")
        if path.startswith(PRODUCT) and path.endswith((".cc", ".h")):
            if len(lines) - 1 > MAX_FILE:
                problems.append(f"{path}: {len(lines) - 1} lines (at most {MAX_FILE})")
            for first, length, name in function_lengths(lines):
                if length > MAX_FUNCTION:
                    problems.append(f"{path}:{first}: function {name} of {length} lines "
                                    f"(at most {MAX_FUNCTION})")
    for p in problems:
        print(p)
    print(f"{len(problems)} offences")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))

#!/usr/bin/python3
"""Replace the key table in docs/case-format.md with `grainlift keys --markdown`.

The table sits between the markers <!-- keys:begin --> and <!-- keys:end -->."""
import subprocess
import sys

if len(sys.argv) != 3:
    print(__doc__ + "\nusage: update_case_docs.py GRAINLIFT_BINARY docs/case-format.md",
          file=sys.stderr)
    sys.exit(0 if sys.argv[1:2] in (["-h"], ["--help"]) else 2)
binary, doc = sys.argv[1], sys.argv[2]
table = subprocess.run([binary, "keys", "--markdown"], check=True, capture_output=True,
                       text=True).stdout
text = open(doc, encoding="utf-8").read()
begin, end = "<!-- keys:begin -->\n", "<!-- keys:end -->"
i, j = text.index(begin) + len(begin), text.index(end)
new = text[:i] + table + text[j:]
if new != text:
    open(doc, "w", encoding="utf-8").write(new)
    print(f"updated {doc}")

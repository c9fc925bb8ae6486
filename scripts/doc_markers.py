"""Replace the text between "<!-- MARKER:begin -->" and "<!-- MARKER:end -->" in a document:
how the study scripts paste their tables into docs/ (the text outside the markers is kept)."""
import sys


def replace_between_markers(path, marker, text):
    doc = open(path).read()
    b, e = f"<!-- {marker}:begin -->", f"<!-- {marker}:end -->"
    if b not in doc or e not in doc:
        sys.exit(f"{path}: no {b} ... {e} markers")
    doc = doc[:doc.index(b) + len(b)] + "\n" + text + doc[doc.index(e):]
    open(path, "w").write(doc)

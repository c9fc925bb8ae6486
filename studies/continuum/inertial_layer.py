#!/usr/bin/env python3
"""Where the flow around the intruder is too fast for mu(I) to be well posed.

    inertial_layer.py CONTINUUM_VTU CENTRE_X CENTRE_Y RADIUS [I_HIGH]

Reads the inertial number of a continuum VTU file (output.vtu = true; deal.II's zlib-compressed
binary VTU) and prints, in rings of distance from the intruder surface, how many output points
have I above I_HIGH (default 0.863, the upper end of the well-posed range of Jop's mu(I) with
mu_s 0.38, mu_2 0.64, I_0 0.279; docs/continuum-model.md) and the median I there.
docs/results-continuum.md, section 6, uses it on the spinning no-slip wall.
"""
import base64
import re
import struct
import sys
import zlib

import numpy as np

TYPES = {"Float32": "<f4", "Float64": "<f8", "Int32": "<i4", "Int64": "<i8", "UInt8": "u1"}


def data_arrays(text):
    """name -> flat array of every DataArray (header of uint32 block sizes, then zlib blocks,
    each part base64-encoded on its own)."""
    out = {}
    for m in re.finditer(r"<DataArray([^>]*)>\s*(.*?)\s*</DataArray>", text, re.S):
        attrs, body = m.group(1), m.group(2).strip()
        name = re.search(r'Name="([^"]*)"', attrs)
        kind = re.search(r'type="([^"]*)"', attrs).group(1)
        blocks = struct.unpack("<I", base64.b64decode(body[:8])[:4])[0]
        header_bytes = 4 * (3 + blocks)
        header_chars = 4 * ((header_bytes + 2) // 3)
        header = struct.unpack(f"<{3 + blocks}I",
                               base64.b64decode(body[:header_chars])[:header_bytes])
        data = base64.b64decode(body[header_chars:])
        raw, pos = b"", 0
        for size in header[3:]:
            raw += zlib.decompress(data[pos:pos + size])
            pos += size
        out[name.group(1) if name else "Points"] = np.frombuffer(raw, dtype=TYPES[kind])
    return out


def main():
    if len(sys.argv) not in (5, 6):
        print(__doc__, file=sys.stderr)
        return 2
    arrays = data_arrays(open(sys.argv[1]).read())
    cx, cy, radius = map(float, sys.argv[2:5])
    i_high = float(sys.argv[5]) if len(sys.argv) == 6 else 0.863
    points = arrays["Points"].reshape(-1, 3)
    inertial = arrays["inertial_number"]
    gap = (np.hypot(points[:, 0] - cx, points[:, 1] - cy) - radius) / radius
    print(f"{len(inertial)} points, {int((inertial > i_high).sum())} with I > {i_high:g}")
    print("| (r - R) / R | points | with I > I_high | median I |")
    print("|---|---|---|---|")
    for lo, hi in ((0, 0.035), (0.035, 0.07), (0.07, 0.15), (0.15, 0.3), (0.3, 1), (1, np.inf)):
        ring = (gap >= lo - 1e-9) & (gap < hi)
        if ring.any():
            print(f"| {lo:g}-{hi:g} | {int(ring.sum())} | "
                  f"{int((ring & (inertial > i_high)).sum())} "
                  f"| {np.median(inertial[ring]):.3g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Writes cloth.obj: the flat cloth of testscenes/flat.

A flat square, 2 x 2 world units, in the plane z = 0 (x, y in [-1, 1]),
front normal +z (the cloth volume lies below, z < 0), as 2 x 2 quads on a
3 x 3 grid of shared vertices and UVs: u = (x + 1) / 2, v = (y + 1) / 2.
Faces run counter-clockwise seen from +z. One UV unit is 2 world units.

Usage: make_cloth.py [OUT.obj]   (default: cloth.obj next to this script)
"""

import os
import sys

N = 2  # quads per side
SIZE = 2.0  # world units


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "cloth.obj")
    with open(out, "w", newline="\n") as f:
        f.write("# clothbake testscenes/flat/cloth.obj, written by make_cloth.py; do not edit.\n")
        f.write(f"# {N} x {N} quads, a flat {SIZE:g} x {SIZE:g} square in z = 0, front +z;\n")
        f.write("# u along x, v along y over [0, 1].\n")
        f.write("o cloth\n")
        for j in range(N + 1):
            for i in range(N + 1):
                f.write(f"v {SIZE * (i / N - 0.5):.6f} {SIZE * (j / N - 0.5):.6f} 0.000000\n")
        for j in range(N + 1):
            for i in range(N + 1):
                f.write(f"vt {i / N:.6f} {j / N:.6f}\n")
        for j in range(N):
            for i in range(N):
                a = j * (N + 1) + i + 1  # 1-based; counter-clockwise seen from +z
                c = [a, a + 1, a + N + 2, a + N + 1]
                f.write("f " + " ".join(f"{k}/{k}" for k in c) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()

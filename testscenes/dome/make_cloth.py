"""Writes cloth.obj: a dome (spherical cap, radius 1, centre at the origin,
pole +z) of 24 x 24 quads with UVs running with the face winding
(counter-clockwise seen from outside). Point (x, y) of [-1, 1]^2 is the
azimuthal equidistant projection of the sphere: polar angle 50 deg x
sqrt(x^2 + y^2) (the edges' midpoints 50 degrees from the pole, the corners
71), so the UV map is isometric along the meridians and stretched by
sin(theta) / theta across them (at most 24 %, at the corners): curvature,
not UV stretch. UV = ((x + 1) / 2, (y + 1) / 2).
    /usr/bin/python3 make_cloth.py
"""
import math
import os

N = 24
THETA = math.radians(50.0)


def point(i, j):
    x, y = -1.0 + 2.0 * i / N, -1.0 + 2.0 * j / N
    rho = math.hypot(x, y)
    theta, phi = THETA * rho, math.atan2(y, x)
    p = (math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta))
    return p, ((x + 1.0) / 2.0, (y + 1.0) / 2.0)


lines = ["# dome: spherical cap, radius 1, 24 x 24 quads (make_cloth.py)"]
uvs = []
for j in range(N + 1):
    for i in range(N + 1):
        p, uv = point(i, j)
        lines.append("v %.6f %.6f %.6f" % p)
        uvs.append(uv)
lines += ["vt %.6f %.6f" % uv for uv in uvs]
for j in range(N):
    for i in range(N):
        a = j * (N + 1) + i + 1
        b, c, d = a + 1, a + N + 2, a + N + 1
        lines.append(f"f {a}/{a} {b}/{b} {c}/{c} {d}/{d}")
here = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(here, "cloth.obj"), "w") as f:
    f.write("\n".join(lines) + "\n")

#!/usr/bin/env python3
"""Writes the meshes of ../extreme.toml (deterministic; run from this folder)."""
import math
import random

rng = random.Random(8)


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def write(name, triangles, comment):
    """triangles: list of three (position, normal) pairs each."""
    with open(name, "w") as f:
        f.write(f"# {comment}\n")
        for t in triangles:
            for p, _ in t:
                f.write("v %.6g %.6g %.6g\n" % tuple(p))
        for t in triangles:
            for _, n in t:
                f.write("vn %.4g %.4g %.4g\n" % tuple(n))
        for i in range(len(triangles)):
            a, b, c = 3 * i + 1, 3 * i + 2, 3 * i + 3
            f.write(f"f {a}//{a} {b}//{b} {c}//{c}\n")


# A closed box, 6 units wide, around the camera.
corners = [[3.0 if (i >> k) & 1 else -3.0 for k in range(3)] for i in range(8)]
faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
box = []
for q in faces:
    p = [corners[i] for i in q]
    center = [sum(c[k] for c in p) / 4 for k in range(3)]
    n = unit([-c for c in center])
    box.append([(p[0], n), (p[1], n), (p[2], n)])
    box.append([(p[0], n), (p[2], n), (p[3], n)])
write("box.obj", box, "a closed box around the camera: every triangle crosses the near plane or lies behind it")

# A thousand full-screen layers, a million pixels wide, cutting through each other.
layers = []
for i in range(1000):
    z = -0.5 - 1.5 * i / 1000
    tx, ty = rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)
    s = 16000.0 if i % 10 == 0 else 40.0
    tri = []
    for x, y in [(-s, -s), (s, -s), (0.0, s)]:
        dz = (tx * x + ty * y) * (0.002 if s > 100 else 0.05)
        n = unit([rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), 1.0])
        tri.append(([x, y, z + dz], n))
    layers.append(tri)
write("layers.obj", layers, "1000 overlapping full-screen triangles (depth complexity 1000), every tenth 32000 units wide")

# Slivers, a needle fan and degenerate triangles.
slivers = []
up = [0.0, 0.0, 1.0]
for i in range(60):
    y = rng.uniform(-0.4, 0.4)
    slivers.append([([-2.0, y, -0.45], up), ([2.0, y + rng.uniform(-0.3, 0.3), -0.45], up), ([-2.0, y + 0.0004, -0.45], up)])
center = [0.2, -0.1, -0.44]
for i in range(120):
    a0, a1 = 2 * math.pi * i / 120, 2 * math.pi * (i + 1) / 120
    r = 0.2
    slivers.append([(center, up), ([center[0] + r * math.cos(a0), center[1] + r * math.sin(a0), center[2]], up),
                    ([center[0] + r * math.cos(a1), center[1] + r * math.sin(a1), center[2]], up)])
for i in range(20):
    p = [rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), -0.43]
    q = [p[0] + 0.1, p[1] + 0.05, p[2]]
    r = [p[0] + 0.2, p[1] + 0.1, p[2]]
    slivers.append([(p, up), (q, up), (r if i % 2 else p, up)])
write("slivers.obj", slivers, "slivers 1/2000 units wide, a fan of 120 needles, 20 degenerate triangles")

# A ground plane from behind the camera to beyond the box.
g = [[-400.0, -1.0, 50.0], [400.0, -1.0, 50.0], [400.0, -1.0, -60.0], [-400.0, -1.0, -60.0]]
n = [0.0, 1.0, 0.0]
write("ground.obj", [[(g[0], n), (g[1], n), (g[2], n)], [(g[0], n), (g[2], n), (g[3], n)]],
      "a ground plane through the near plane")

#!/usr/bin/env python3
"""make_models.py: writes the model files of scenes/mesh.scene (scenes/models/): a torus and a
geodesic sphere (an icosahedron subdivided twice) as OBJ with one MTL file. Made here, no
third-party data: run `python3 tools/make_models.py` from the repository root to remake them."""
import math
import os

OUT = os.path.join(os.path.dirname(__file__), "..", "scenes", "models")


def torus(major, minor, rings, sides):
    verts, faces = [], []
    for i in range(rings):
        a = 2 * math.pi * i / rings
        for j in range(sides):
            b = 2 * math.pi * j / sides
            r = major + minor * math.cos(b)
            verts.append((r * math.cos(a), minor * math.sin(b), r * math.sin(a)))
    for i in range(rings):
        for j in range(sides):
            k = lambda ii, jj: (ii % rings) * sides + (jj % sides) + 1
            faces.append((k(i, j), k(i, j + 1), k(i + 1, j + 1), k(i + 1, j)))
    return verts, faces


def geosphere(levels):
    t = (1 + 5 ** 0.5) / 2
    verts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
             (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [tuple(c / math.sqrt(sum(x * x for x in v)) for c in v) for v in verts]
    for _ in range(levels):
        cache, out = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(verts[a][c] + verts[b][c]) / 2 for c in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                verts.append(tuple(x / n for x in m))
                cache[key] = len(verts) - 1
            return cache[key]

        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = out
    return verts, [tuple(i + 1 for i in f) for f in faces]


def write_obj(name, material, verts, faces):
    with open(os.path.join(OUT, name), "w") as f:
        f.write("# %s: made by tools/make_models.py\nmtllib models.mtl\n" % name)
        for v in verts:
            f.write("v %.6f %.6f %.6f\n" % v)
        f.write("usemtl %s\n" % material)
        for face in faces:
            f.write("f %s\n" % " ".join(str(i) for i in face))


os.makedirs(OUT, exist_ok=True)
with open(os.path.join(OUT, "models.mtl"), "w") as f:
    f.write("# models.mtl: made by tools/make_models.py\n"
            "newmtl copper\nKd 0.55 0.25 0.12\nKs 0.35 0.3 0.25\nNs 60\n"
            "newmtl glass\nKd 1 1 1\nNi 1.5\nd 0\nillum 4\n")
write_obj("torus.obj", "copper", *torus(1.0, 0.35, 48, 24))
write_obj("geosphere.obj", "glass", *geosphere(2))

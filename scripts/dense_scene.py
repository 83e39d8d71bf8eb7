#!/usr/bin/env python3
"""Write a copy of a scene whose mesh files are split into four triangles per triangle N times (4^N as many).

Usage: scripts/dense_scene.py SCENE.json LEVELS OUT_DIR

The frame benchmark runs it to show that the host's cost of a frame does not grow with the triangle count
(docs/results.md). Only OBJ meshes with triangle faces ("f a b c", any of the v/vt/vn index forms) are split;
box meshes and the rest of the scene are copied as they are. Shared edges get one midpoint, so closed meshes stay
closed.
"""
import json
import os
import sys


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):  # fan-triangulate polygons
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def subdivide(verts, faces):
    verts = list(verts)
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            pa, pb = verts[a], verts[b]
            verts.append(tuple(0.5 * (x + y) for x, y in zip(pa, pb)))
            mid[key] = len(verts) - 1
        return mid[key]

    out = []
    for a, b, c in faces:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return verts, out


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    scene_path, levels, out_dir = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    if not 0 <= levels <= 6:
        sys.exit(f"{sys.argv[0]}: levels {levels} must be in [0, 6]")
    with open(scene_path) as f:
        scene = json.load(f)
    os.makedirs(out_dir, exist_ok=True)
    base = os.path.dirname(os.path.abspath(scene_path))
    total = 0
    for name, mesh in scene.get("meshes", {}).items():
        if "path" not in mesh:
            continue
        verts, faces = read_obj(os.path.join(base, mesh["path"]))
        for _ in range(levels):
            verts, faces = subdivide(verts, faces)
        total += len(faces)
        out = os.path.join(out_dir, f"{name}_x{4 ** levels}.obj")
        with open(out + ".part", "w") as f:
            f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in verts)
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
        os.replace(out + ".part", out)
        mesh["path"] = os.path.abspath(out)
    out_scene = os.path.join(out_dir, os.path.basename(scene_path).replace(".json", f"_x{4 ** levels}.json"))
    with open(out_scene + ".part", "w") as f:
        json.dump(scene, f, indent=1)
    os.replace(out_scene + ".part", out_scene)
    print(f"{out_scene}: {total} triangles in its mesh files")


if __name__ == "__main__":
    main()

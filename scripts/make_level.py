#!/usr/bin/python3
"""Write a town level for rtsdf: a scene folder (level.json + meshes/*.obj), deterministic from a seed.

Usage: scripts/make_level.py --out DIR [--size METRES] [--seed N] [--meshes DIR]

The level is SIZE x SIZE metres (50, 200 and 1000 are the sizes the cascades are measured on; any size in
[25, 4000] works) of square blocks 25 m apart, separated by streets 8 m wide, in metres with +y up:
- ground: one slab, top at y = 0;
- buildings with thin walls: a few generated shells (four walls 0.15-0.3 m thick with a door gap, a floor slab
  and a roof), placed one per block and turned by a multiple of 90 degrees;
- props: the bundled bunny and teapot (copied from --meshes, data/meshes by default), scaled to 0.4-1.2 m, on the
  pavements, and generated benches (a seat and two legs);
- vehicles: a generated car (a body and a cabin), instances driving along the streets at 8-14 m/s with instance
  keyframes (rigid, turned to face along the street);
- a sun with a 0.27 degree angular radius;
- a camera path: walking at 1.4 m/s at eye height (1.7 m) for the first WALK_SECONDS, then driving at 12 m/s at
  1.2 m along the streets; the scene's comment gives both time spans.

The same --seed and --size always write the same bytes (the generator uses its own random.Random and writes numbers
with fixed precision); a different seed moves the buildings, props and vehicles. The level's size changes how many
blocks there are, not what a block looks like: a 1000 m level is many 50 m levels side by side, as the cascade
measurements need (the same detail near the camera whatever the size).
"""
import argparse
import json
import math
import os
import random
import shutil
import sys

BLOCK = 25.0  # metres from one street's centre to the next
STREET = 8.0  # street width
WALK_SPEED, DRIVE_SPEED = 1.4, 12.0
WALK_SECONDS = 20.0
EYE_WALK, EYE_DRIVE = 1.7, 1.2


def fmt(x):
    """A number with fixed precision, so that the output is byte-identical across runs and machines."""
    s = f"{x:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


class Obj:
    """An OBJ of closed axis-aligned boxes (each 12 outward triangles)."""

    def __init__(self):
        self.verts, self.faces = [], []

    def box(self, lo, hi):
        base = len(self.verts) + 1
        for z in (lo[2], hi[2]):
            for y in (lo[1], hi[1]):
                for x in (lo[0], hi[0]):
                    self.verts.append((x, y, z))
        # corners: index = x + 2y + 4z; quads counter-clockwise seen from outside
        quads = [(0, 4, 6, 2), (1, 3, 7, 5), (0, 1, 5, 4), (2, 6, 7, 3), (0, 2, 3, 1), (4, 5, 7, 6)]
        for a, b, c, d in quads:
            self.faces.append((base + a, base + b, base + c))
            self.faces.append((base + a, base + c, base + d))

    def text(self, comment):
        lines = [f"# {comment}"]
        lines += ["v " + " ".join(fmt(c) for c in v) for v in self.verts]
        lines += ["f {} {} {}".format(*f) for f in self.faces]
        return "\n".join(lines) + "\n"


def building_mesh(rng):
    """A shell of thin walls: width, depth, height, wall thickness; a door gap in the front wall (-z)."""
    w, d = rng.uniform(8.0, 14.0), rng.uniform(8.0, 14.0)
    h, t = rng.uniform(3.0, 12.0), rng.uniform(0.15, 0.3)
    door = 1.2
    o = Obj()
    x0, x1, z0, z1 = -w / 2, w / 2, -d / 2, d / 2
    o.box((x0, 0.0, z1 - t), (x1, h, z1))  # back wall
    o.box((x0, 0.0, z0 + t), (x0 + t, h, z1 - t))  # left wall
    o.box((x1 - t, 0.0, z0 + t), (x1, h, z1 - t))  # right wall
    o.box((x0, 0.0, z0), (-door / 2, h, z0 + t))  # front wall, left of the door
    o.box((door / 2, 0.0, z0), (x1, h, z0 + t))  # front wall, right of the door
    o.box((-door / 2, 2.2, z0), (door / 2, h, z0 + t))  # above the door
    o.box((x0 + t, 0.0, z0 + t), (x1 - t, 0.1, z1 - t))  # floor slab
    o.box((x0, h, z0), (x1, h + t, z1))  # roof
    return o, (w, d, h, t)


def car_mesh():
    o = Obj()
    o.box((-2.1, 0.3, -0.9), (2.1, 1.0, 0.9))  # body, along +x
    o.box((-1.0, 1.0, -0.8), (1.0, 1.5, 0.8))  # cabin
    return o


def bench_mesh():
    o = Obj()
    o.box((-0.9, 0.42, -0.22), (0.9, 0.47, 0.22))  # seat: a 5 cm plate
    o.box((-0.8, 0.0, -0.2), (-0.74, 0.42, 0.2))  # legs
    o.box((0.74, 0.0, -0.2), (0.8, 0.42, 0.2))
    return o


def prop_scale(path):
    """The scale that makes the mesh's largest side 1 m, read from its vertices."""
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                v = [float(x) for x in line.split()[1:4]]
                lo = [min(a, b) for a, b in zip(lo, v)]
                hi = [max(a, b) for a, b in zip(hi, v)]
    return 1.0 / max(h - l for l, h in zip(lo, hi)), -lo[1]


def street_lines(size):
    """The coordinates of the streets' centre lines along one axis (the level spans [-size/2, size/2])."""
    n = max(1, int(round(size / BLOCK)))
    return [-size / 2 + BLOCK * i for i in range(n + 1)]


def camera_path(size, lines):
    """Walk along the first street (+x) at eye height, then drive along the streets, turning at crossings."""
    keys = []
    mid = lines[len(lines) // 2]
    z = mid + 1.5
    x = -size / 2 + 2.0
    t = 0.0
    walk_end = min(x + WALK_SPEED * WALK_SECONDS, size / 2 - 2.0)
    keys.append((t, (x, EYE_WALK, z), (x + 10.0, EYE_WALK - 0.3, z)))
    t += (walk_end - x) / WALK_SPEED
    x = walk_end
    keys.append((t, (x, EYE_WALK, z), (x + 10.0, EYE_WALK - 0.3, z)))
    walk_seconds = t
    # Driving: on along +x to the level's edge, then a turn onto the last street line, towards +z.
    t += 1.0
    keys.append((t, (x, EYE_DRIVE, z), (x + 10.0, EYE_DRIVE, z)))
    x_end = lines[-1] - 3.0 if len(lines) > 1 else size / 2 - 3.0
    if x_end > x:
        t += (x_end - x) / DRIVE_SPEED
        x = x_end
        keys.append((t, (x, EYE_DRIVE, z), (x + 10.0, EYE_DRIVE, z)))
    t += 1.0
    keys.append((t, (x + 1.0, EYE_DRIVE, z + 1.0), (x + 1.0, EYE_DRIVE, z + 11.0)))
    z_end = size / 2 - 3.0
    if z_end > z + 1.0:
        t += (z_end - z - 1.0) / DRIVE_SPEED
        keys.append((t, (x + 1.0, EYE_DRIVE, z_end), (x + 1.0, EYE_DRIVE, z_end + 10.0)))
    frames = [{"time": float(fmt(k[0])), "position": [float(fmt(c)) for c in k[1]],
               "look_at": [float(fmt(c)) for c in k[2]]} for k in keys]
    return frames, walk_seconds, t


def vehicle(rng, i, size, lines):
    """A car driving the length of a street line, along x or z, at 8-14 m/s (rigid keyframes)."""
    along_x = rng.random() < 0.5
    line = rng.choice(lines)
    lane = rng.choice((-2.0, 2.0))
    speed = rng.uniform(8.0, 14.0)
    start, end = -size / 2 + 3.0, size / 2 - 3.0
    if lane < 0:
        start, end = end, start
    seconds = abs(end - start) / speed
    if along_x:
        p0, p1, yaw = (start, 0.0, line + lane), (end, 0.0, line + lane), 0.0 if end > start else 180.0
    else:
        p0, p1, yaw = (line + lane, 0.0, start), (line + lane, 0.0, end), -90.0 if end > start else 90.0
    return {"name": f"car{i}", "mesh": "car", "rotate": [0, yaw, 0], "animation": {"keyframes": [
        {"time": 0, "translate": [float(fmt(c)) for c in p0]},
        {"time": float(fmt(seconds)), "translate": [float(fmt(c)) for c in p1]}]}}


def level(size, seed, meshes_dir, out):
    rng = random.Random(seed)
    lines = street_lines(size)
    os.makedirs(os.path.join(out, "meshes"), exist_ok=True)
    meshes = {"ground": {"box": [size + 2 * STREET, 0.2, size + 2 * STREET]}}
    files = {}
    kinds = []
    for k in range(6):
        obj, dims = building_mesh(rng)
        name = f"building{k}"
        files[name] = obj.text(f"{name}: shell {dims[0]:.2f} x {dims[1]:.2f} x {dims[2]:.2f} m, walls "
                               f"{dims[3]:.3f} m (make_level.py --seed {seed})")
        kinds.append(name)
    files["car"] = car_mesh().text("car: body and cabin, 4.2 m long, along +x")
    files["bench"] = bench_mesh().text("bench: a 5 cm seat on two legs")
    for name, text in files.items():
        meshes[name] = {"path": f"meshes/{name}.obj"}
        with open(os.path.join(out, "meshes", f"{name}.obj"), "w") as f:
            f.write(text)
    props = {}
    for name in ("bunny", "teapot"):
        src = os.path.join(meshes_dir, f"{name}.obj")
        shutil.copyfile(src, os.path.join(out, "meshes", f"{name}.obj"))
        meshes[name] = {"path": f"meshes/{name}.obj"}
        props[name] = prop_scale(src)

    instances = [{"name": "ground", "mesh": "ground", "translate": [0, -0.1, 0]}]
    centres = [0.5 * (a + b) for a, b in zip(lines, lines[1:])] or [0.0]
    for i, cx in enumerate(centres):
        for j, cz in enumerate(centres):
            kind = rng.choice(kinds)
            yaw = 90 * rng.randrange(4)
            at = [float(fmt(cx + rng.uniform(-1, 1))), 0, float(fmt(cz + rng.uniform(-1, 1)))]
            instances.append({"name": f"house_{i}_{j}", "mesh": kind, "rotate": [0, yaw, 0], "translate": at})
            for p in range(3):  # on the pavement along the block's -z side
                px = cx + rng.uniform(-BLOCK / 2 + STREET / 2 + 0.5, BLOCK / 2 - STREET / 2 - 0.5)
                pz = cz - BLOCK / 2 + STREET / 2 + 0.8
                choice = rng.choice(("bunny", "teapot", "bench"))
                inst = {"name": f"prop_{i}_{j}_{p}", "mesh": choice, "rotate": [0, float(fmt(rng.uniform(0, 360))), 0]}
                if choice == "bench":
                    inst["translate"] = [float(fmt(px)), 0, float(fmt(pz))]
                else:
                    size_m = rng.uniform(0.4, 1.2)
                    s, lift = props[choice]
                    inst["scale"] = float(fmt(s * size_m))
                    inst["translate"] = [float(fmt(px)), float(fmt(lift * s * size_m)), float(fmt(pz))]
                instances.append(inst)
    cars = max(2, int(size / 25))
    for i in range(cars):
        instances.append(vehicle(rng, i, size, lines))

    frames, walk_seconds, end = camera_path(size, lines)
    scene = {
        "rtsdf_scene": 1,
        "comment": (f"Town level {fmt(size)} m, seed {seed} (scripts/make_level.py): {len(centres) ** 2} blocks, "
                    f"{cars} cars; camera walks at {WALK_SPEED} m/s for t in [0, {fmt(walk_seconds)}] s, "
                    f"then drives at {DRIVE_SPEED} m/s until t = {fmt(end)} s."),
        "meshes": meshes,
        "instances": instances,
        "lights": [{"name": "sun", "type": "directional", "direction": [-0.45, -1.0, -0.3],
                    "angular_radius_deg": 0.27, "color": [1.0, 0.96, 0.9], "intensity": 3.0}],
        "camera": {"fov_deg": 60, "keyframes": frames},
    }
    with open(os.path.join(out, "level.json"), "w") as f:
        json.dump(scene, f, indent=1, sort_keys=False)
        f.write("\n")
    return scene


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, help="the folder to write (level.json, meshes/)")
    ap.add_argument("--size", type=float, default=200.0, help="the level's side in metres, in [25, 4000] (200)")
    ap.add_argument("--seed", type=int, default=1, help="the random seed (1)")
    ap.add_argument("--meshes", default=os.path.join(here, "..", "data", "meshes"),
                    help="the folder with bunny.obj and teapot.obj (data/meshes)")
    a = ap.parse_args()
    if not (25.0 <= a.size <= 4000.0):
        sys.exit(f"make_level.py: --size {a.size} must be in [25, 4000] metres")
    for name in ("bunny.obj", "teapot.obj"):
        if not os.path.isfile(os.path.join(a.meshes, name)):
            sys.exit(f"make_level.py: --meshes {a.meshes}: no {name}")
    scene = level(a.size, a.seed, a.meshes, a.out)
    print(f"{a.out}/level.json: {len(scene['instances'])} instances; {scene['comment']}")


if __name__ == "__main__":
    main()

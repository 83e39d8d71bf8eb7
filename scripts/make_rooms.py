#!/usr/bin/env python3
"""Write the default room tiled N x N times, 2.2 units apart: the town of rooms that a single box cannot hold at
render's defaults and cascades can (docs/cascades.md). Room (0, 0) keeps the default scene's camera and light, so the
same view of the same room can be compared alone and inside the town.

    scripts/make_rooms.py --rooms 16 -o build/rooms16/rooms.json
"""
import argparse
import json
import os
import shutil
import sys

SPACING = 2.2


def tile(room, n):
    town = dict(room)
    town["comment"] = f"The default room tiled {n} x {n} times, {SPACING} units apart (scripts/make_rooms.py)."
    town["instances"] = []
    for i in range(n):
        for j in range(n):
            offset = [SPACING * i, 0.0, SPACING * j]
            for inst in room["instances"]:
                copy = json.loads(json.dumps(inst))
                copy["name"] = f"{inst['name']}_{i}_{j}"
                copy["translate"] = [a + b for a, b in zip(inst.get("translate", [0, 0, 0]), offset)]
                orbit = copy.get("animation", {}).get("orbit")
                if orbit:
                    orbit["center"] = [a + b for a, b in zip(orbit["center"], offset)]
                town["instances"].append(copy)
    return town


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rooms", type=int, default=16, help="rooms along each side (default 16)")
    parser.add_argument("--room", default=os.path.join(here, "..", "data", "scenes", "default.json"),
                        help="the room's scene file (default: the bundled default scene)")
    parser.add_argument("-o", "--output", required=True, help="the scene file to write (its folder is created)")
    a = parser.parse_args()
    if not 1 <= a.rooms <= 64:
        sys.exit(f"--rooms {a.rooms}: give 1 to 64")
    with open(a.room) as f:
        room = json.load(f)
    out_dir = os.path.dirname(os.path.abspath(a.output))
    os.makedirs(out_dir, exist_ok=True)
    # A scene's mesh files may not lie outside its folder: copy them beside the new scene.
    room_dir = os.path.dirname(os.path.abspath(a.room))
    for mesh in room["meshes"].values():
        if "path" in mesh:
            name = os.path.basename(mesh["path"])
            shutil.copyfile(os.path.join(room_dir, mesh["path"]), os.path.join(out_dir, name))
            mesh["path"] = name
    tmp = a.output + ".tmp"
    with open(tmp, "w") as f:
        json.dump(tile(room, a.rooms), f, indent=1)
    os.replace(tmp, a.output)


if __name__ == "__main__":
    main()

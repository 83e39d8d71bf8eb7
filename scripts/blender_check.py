"""Run inside Blender (scripts/blender_check.sh): import an rtsdf bake written with --up z, mesh it with the Volume to
Mesh modifier and check that the mesh stands upright within half a voxel of the scene's bounds.

    blender -b --factory-startup --python scripts/blender_check.py -- BAKE.vdb MESH.obj SCALE [PICTURE.png]

MESH.obj is the scene's mesh (Y-up, as baked) and SCALE the scene's uniform scale of it; its bounds scaled and turned
to Z-up, (x, y, z) -> (x, -z, y), are what the mesh from Blender must match at threshold 0. Prints one line per threshold and exits 1 when the check fails.
"""
import math
import sys

import bpy

TOLERANCE_VOXELS = 1.0


def obj_bounds_z_up(path, scale):
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                x, y, z = (scale * float(v) for v in line.split()[1:4])
                p = (x, -z, y)  # Y-up to Z-up, as rtsdf bake --up z turns the grid
                lo = [min(a, b) for a, b in zip(lo, p)]
                hi = [max(a, b) for a, b in zip(hi, p)]
    return lo, hi


def volume_to_mesh_bounds(volume, grid, threshold):
    mesh = bpy.data.meshes.new(f"mesh {threshold}")
    obj = bpy.data.objects.new(f"mesh {threshold}", mesh)
    bpy.context.scene.collection.objects.link(obj)
    mod = obj.modifiers.new("volume to mesh", "VOLUME_TO_MESH")
    mod.object = volume
    mod.grid_name = grid
    mod.threshold = threshold
    mod.resolution_mode = "GRID"
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    me = evaluated.to_mesh()
    points = [evaluated.matrix_world @ v.co for v in me.vertices]
    if not points:
        return obj, None
    lo = [min(p[i] for p in points) for i in range(3)]
    hi = [max(p[i] for p in points) for i in range(3)]
    return obj, (lo, hi, len(points), len(me.polygons))


def render(picture, target, lo, hi):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False  # Debian's Blender is built without OpenImageDenoise
    scene.render.resolution_x, scene.render.resolution_y = 480, 360
    scene.render.filepath = picture
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    size = max(b - a for a, b in zip(lo, hi))
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.location = (centre[0] + 1.2 * size, centre[1] - 2.0 * size, centre[2] + 0.6 * size)
    direction = [c - l for c, l in zip(centre, cam.location)]
    cam.rotation_euler = (math.atan2(math.hypot(direction[0], direction[1]), -direction[2]), 0.0,
                          math.atan2(direction[1], direction[0]) - math.pi / 2)
    scene.camera = cam
    light = bpy.data.lights.new("sun", "SUN")
    light.energy = 4.0
    sun = bpy.data.objects.new("sun", light)
    sun.rotation_euler = (0.6, 0.2, 0.8)
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.color = (0.12, 0.13, 0.15)
    scene.world = world
    for o in scene.objects:  # only the mesh at threshold 0 is shown
        o.hide_render = o.type in {"MESH", "VOLUME"} and o != target
    bpy.ops.render.render(write_still=True)


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    vdb, scene_mesh, scale = args[0], args[1], float(args[2])
    picture = args[3] if len(args) > 3 else ""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.object.volume_import(filepath=vdb)
    volume = bpy.context.selected_objects[0]
    volume.data.grids.load()
    grid = volume.data.grids["surface"]
    voxel = grid.matrix_object.col[0].xyz.length
    want_lo, want_hi = obj_bounds_z_up(scene_mesh, scale)
    print(f"blender {bpy.app.version_string}: {vdb}: grid 'surface', voxel size {voxel:.6g}")
    print(f"scene bounds (Z-up): ({', '.join(f'{v:.4f}' for v in want_lo)}) to "
          f"({', '.join(f'{v:.4f}' for v in want_hi)}), size "
          f"{', '.join(f'{b - a:.4f}' for a, b in zip(want_lo, want_hi))}")
    ok = True
    shown = None
    for threshold in (0.0, 0.1):
        obj, found = volume_to_mesh_bounds(volume, "surface", threshold)
        if found is None:
            print(f"threshold {threshold}: empty mesh")
            ok = ok and threshold != 0.0
            continue
        lo, hi, vertices, faces = found
        worst = max(max(abs(a - b) for a, b in zip(lo, want_lo)), max(abs(a - b) for a, b in zip(hi, want_hi)))
        print(f"threshold {threshold}: bounds ({', '.join(f'{v:.4f}' for v in lo)}) to "
              f"({', '.join(f'{v:.4f}' for v in hi)})")
        print(f"threshold {threshold}: {vertices} vertices, {faces} faces, size "
              f"{', '.join(f'{b - a:.4f}' for a, b in zip(lo, hi))}; farthest bound {worst:.4f} = "
              f"{worst / voxel:.2f} voxels from the scene's")
        if threshold == 0.0:
            shown = (obj, lo, hi)
            size, want = [b - a for a, b in zip(lo, hi)], [b - a for a, b in zip(want_lo, want_hi)]
            # Upright: its height is the scene's height (its extent along Y before the turn), not its depth.
            upright = abs(size[2] - want[2]) < abs(size[2] - want[1]) and abs(size[1] - want[1]) < abs(size[1] - want[2])
            # Marching cubes (volumeToMesh, which the modifier runs) places no vertex past the last voxel centre
            # inside a feature thinner than a voxel: the ear tips end up to a voxel short. Smooth sides: far less.
            within = worst <= TOLERANCE_VOXELS * voxel
            sides = max(abs(lo[0] - want_lo[0]), abs(hi[0] - want_hi[0]))
            print(f"check: upright along Z {'yes' if upright else 'NO'}; every bound within {TOLERANCE_VOXELS} voxel "
                  f"{'yes' if within else 'NO'} (farthest {worst / voxel:.2f}); the sides along X within "
                  f"{sides / voxel:.2f} voxels")
            ok = ok and upright and within
    if picture and shown:
        render(picture, *shown)
        print(f"wrote {picture}")
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


main()

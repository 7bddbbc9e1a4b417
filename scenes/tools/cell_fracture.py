# Blender Cell Fracture, headless: fractures a mesh into cells with a fixed seed and exports the
# pieces as one OBJ (one `o` group per piece) and the object they were cut from as the exterior.
#
#   blender -b --factory-startup -noaudio --python-exit-code 1 --python scenes/tools/cell_fracture.py -- \
#       INPUT|cube OUT_PIECES.obj OUT_EXTERIOR.obj --cells 8 --seed 1 --margin 0.001 [--triangulate] [--decimate 0.5]
#       [--split]   (OUT_PIECES is then a folder: one OBJ per piece, shard_000.obj ...)
#
# INPUT is an OBJ (read with Blender's OBJ importer, Y up) or `cube` (Blender's default 2x2x2
# cube). --margin is the add-on's margin (its default is 0.001). The add-on's own randomness (the
# ±0.0005 jitter of each cell's corners) is Python's `random`, seeded here with --seed; the cell
# centres are --cells points drawn with the same seed inside the object's box. Without
# --triangulate the pieces keep Blender's n-gons. Tested with Debian 12's blender 3.4.1.
import argparse
import os
import random
import sys

import addon_utils
import bpy


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="cell_fracture.py")
    p.add_argument("input")
    p.add_argument("pieces")
    p.add_argument("exterior")
    p.add_argument("--cells", type=int, default=8)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--margin", type=float, default=0.001)
    p.add_argument("--triangulate", action="store_true")
    p.add_argument("--split", action="store_true", help="PIECES is a folder: one OBJ per piece (shards)")
    p.add_argument("--decimate", type=float, default=1.0, help="collapse ratio applied to the input first (1 = none)")
    return p.parse_args(argv)


def load(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path == "cube":
        bpy.ops.mesh.primitive_cube_add(size=2.0)
    else:
        bpy.ops.wm.obj_import(filepath=path)
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    return obj


def decimate(obj, ratio):
    if ratio >= 1.0:
        return
    mod = obj.modifiers.new(name="Decimate", type="DECIMATE")
    mod.ratio = ratio
    mod.use_collapse_triangulate = True
    bpy.ops.object.modifier_apply(modifier=mod.name)


def add_cell_points(obj, count, seed):
    rng = random.Random(seed)
    lo = [min(v.co[a] for v in obj.data.vertices) for a in range(3)]
    hi = [max(v.co[a] for v in obj.data.vertices) for a in range(3)]
    pts = [tuple(lo[a] + (0.15 + 0.7 * rng.random()) * (hi[a] - lo[a]) for a in range(3)) for _ in range(count)]
    mesh = bpy.data.meshes.new("cell_points")
    mesh.from_pydata(pts, [], [])
    points = bpy.data.objects.new("cell_points", mesh)
    bpy.context.collection.objects.link(points)
    points.parent = obj
    return points


def export(objects, path, triangulate):
    bpy.ops.object.select_all(action="DESELECT")
    for o in objects:
        o.select_set(True)
    bpy.ops.wm.obj_export(filepath=path, export_selected_objects=True, export_triangulated_mesh=triangulate,
                          export_materials=False, export_normals=False, export_uv=False, apply_modifiers=True)


def main():
    args = parse()
    obj = load(args.input)
    addon_utils.enable("object_fracture_cell", default_set=True)  # after the factory settings, which reset add-ons
    decimate(obj, args.decimate)
    export([obj], args.exterior, True)
    points = add_cell_points(obj, args.cells, args.seed)
    random.seed(args.seed)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.add_fracture_cell_objects(source={"VERT_CHILD"}, margin=args.margin, use_recenter=True,
                                              use_remove_original=True, use_island_split=True)
    pieces = [o for o in bpy.context.scene.objects if o.type == "MESH" and o is not obj and o is not points]
    pieces.sort(key=lambda o: o.name)
    print("cell_fracture.py: %d pieces" % len(pieces))
    if not args.split:
        export(pieces, args.pieces, args.triangulate)
        return
    for i, o in enumerate(pieces):
        export([o], os.path.join(args.pieces, "shard_%03d.obj" % i), args.triangulate)


main()

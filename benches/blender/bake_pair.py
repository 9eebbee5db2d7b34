"""Blender reference for `tutorial13 bake`: builds a HIGH/LOW sphere pair, exports it, and bakes
a tangent-space normal map of HIGH onto LOW with Cycles, timing the bake.

Run (Blender 3.4 or later; tested with Debian's 3.4.1):

    blender -b --factory-startup --python benches/blender/bake_pair.py -- --out DIR \
        [--size 2048] [--samples 1] [--extrusion 0.05] [--max-distance 0.1] [--margin 16] \
        [--margin-type ADJACENT_FACES] [--high-subdiv 9] [--low 32x16] [--amp 0.02] [--freq 12]
        [--cage MIN,MAX] [--cage-twist T]

Writes into DIR:
  high.obj              HIGH, triangulated, smooth vertex normals, UVs (the icosphere's own)
  low.obj, low.mtl      LOW, the very triangles that were baked (triangulated in Blender first)
  low.gltf, low.bin     LOW with MikkTSpace tangents (export_tangents), if the glTF add-on works
  blender_normal.png    the bake, 8-bit RGBA
  blender_normal16.png  the bake, 16-bit RGBA
  blender_timings.json  timings and settings
  cage.obj              with --cage: the cage object the bake used (LOW's faces, its corners moved)

The meshes (Blender object space, Z up; both objects at the origin, unit transform):
  HIGH  an icosphere (2 + 10*4^(s-1) vertices, 20*4^(s-1) triangles; s = 9: 1,310,720 triangles)
        pushed along the radius to r(u) = 1 + F(u), F(u) = A cos(k ux) cos(k uy) cos(k uz), u the
        unit direction, A = --amp, k = --freq. F is smooth everywhere (unlike sin(12 theta) sin(12
        phi), which has cone points at the poles). Its exact normal at the point r(u) u is
            n = normalize(u - (g - (g.u) u) / r),
            g = grad F(u) = -A k (sin(k ux) cos(k uy) cos(k uz), cos(k ux) sin(k uy) cos(k uz),
                                  cos(k ux) cos(k uy) sin(k uz))
        (the gradient of |p| - 1 - F(p/|p|)). The mesh's normals are Blender's smooth-shading
        vertex normals, which approximate n.
  LOW   a UV sphere (--low SEGMENTSxRINGS, radius 1, smooth), its UVs Blender's, triangulated
        (bmesh, BEAUTY) before both bake and export so that Blender's MikkTSpace and any other
        see the same triangles. Its material holds the bake target: an Image Texture node,
        Non-Color, float, alpha, selected and active, connected to nothing.

  CAGE  with --cage MIN,MAX: LOW's mesh, each vertex moved out along its normal by
        MIN + (MAX - MIN) (1 + z) / 2 (thin at the south pole, thick at the north) and by
        --cage-twist T (1 - z^2) along the parallel (east), so that the rays from it run slanted.
        The bake then uses it as its cage object (use_cage, cage_object; cage_extrusion 0), and
        --max-distance 0 means no bound, as Blender's own default.

OBJ axes: wm.obj_export's defaults, forward -Z and up Y, i.e. OBJ (X, Y, Z) = Blender (x, z, -y):
OBJ files are Y-up, the spheres' poles on OBJ's Y axis. HIGH and LOW are exported alike, so the
pair is consistent. F is even in each coordinate and symmetric in them, so in OBJ coordinates it
reads the same, F = A cos(kX) cos(kY) cos(kZ). glTF (export_yup) uses the same mapping.

Bake image conventions: Blender's normal swizzle +X +Y +Z (OpenGL, green up), c = n/2 + 1/2; the
PNG's top row is v = 1 (Blender's pixel row 0 is v = 0, written at the bottom). The image is filled
with (0.5, 0.5, 1, 0) and baked without use_clear (whose fill has alpha 1), so texels the bake does
not reach (outside the UV islands and the margin) keep alpha 0 and the written ones have alpha 1.
"""
import argparse
import array
import json
import math
import os
import sys
import time

import bmesh
import bpy


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="bake_pair.py")
    p.add_argument("--out", required=True)
    p.add_argument("--size", type=int, default=2048)
    p.add_argument("--samples", type=int, default=1)
    p.add_argument("--extrusion", type=float, default=0.05)
    p.add_argument("--max-distance", type=float, default=0.1)
    p.add_argument("--margin", type=int, default=16)
    p.add_argument("--margin-type", default="ADJACENT_FACES", choices=["ADJACENT_FACES", "EXTEND"])
    p.add_argument("--high-subdiv", type=int, default=9)
    p.add_argument("--low", default="32x16", help="SEGMENTSxRINGS of the UV sphere")
    p.add_argument("--amp", type=float, default=0.02)
    p.add_argument("--freq", type=float, default=12.0)
    p.add_argument("--cage", help="MIN,MAX: a cage object LOW's normals out (see the header)")
    p.add_argument("--cage-twist", type=float, default=0.0)
    return p.parse_args(argv)


def triangles(obj):
    obj.data.calc_loop_triangles()
    return len(obj.data.loop_triangles)


def select_only(*objs):
    bpy.ops.object.select_all(action="DESELECT")
    for o in objs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = objs[-1]


def build_high(subdiv, amp, freq):
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdiv, radius=1.0, location=(0, 0, 0))
    obj = bpy.context.active_object
    obj.name = obj.data.name = "HIGH"
    mesh = obj.data
    co = array.array("f", [0.0]) * (3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    cos = math.cos
    for i in range(0, len(co), 3):
        x, y, z = co[i], co[i + 1], co[i + 2]
        s = 1.0 / math.sqrt(x * x + y * y + z * z)
        x, y, z = x * s, y * s, z * s
        r = 1.0 + amp * cos(freq * x) * cos(freq * y) * cos(freq * z)
        co[i], co[i + 1], co[i + 2] = r * x, r * y, r * z
    mesh.vertices.foreach_set("co", co)
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.update()
    return obj


def build_low(segments, rings, size):
    bpy.ops.mesh.primitive_uv_sphere_add(
        segments=segments, ring_count=rings, radius=1.0, calc_uvs=True, location=(0, 0, 0))
    obj = bpy.context.active_object
    obj.name = obj.data.name = "LOW"
    mesh = obj.data
    bm = bmesh.new()
    bm.from_mesh(mesh)
    bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method="BEAUTY", ngon_method="BEAUTY")
    bm.to_mesh(mesh)
    bm.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.update()

    image = bpy.data.images.new("bake_target", size, size, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    mat = bpy.data.materials.new("LOW_bake")
    mat.use_nodes = True
    node = mat.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    for n in mat.node_tree.nodes:
        n.select = False
    node.select = True
    mat.node_tree.nodes.active = node
    mesh.materials.append(mat)
    return obj, image


def build_cage(low, offsets, twist):
    lo, hi = (float(v) for v in offsets.split(","))
    obj = low.copy()
    obj.data = low.data.copy()
    obj.name = obj.data.name = "CAGE"
    bpy.context.collection.objects.link(obj)
    for v in obj.data.vertices:
        p, n = v.co.copy(), v.normal.copy()
        east = n.cross((0.0, 0.0, 1.0))
        if east.length > 1e-6:
            east.normalize()
        v.co = p + n * (lo + (hi - lo) * (1.0 + p.z) / 2.0) + east * (twist * (1.0 - p.z * p.z))
    obj.data.update()
    return obj


def main():
    args = parse_args()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    segments, rings = (int(v) for v in args.low.lower().split("x"))
    t = {}

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene

    t0 = time.perf_counter()
    high = build_high(args.high_subdiv, args.amp, args.freq)
    t["build_high_s"] = time.perf_counter() - t0
    low, image = build_low(segments, rings, args.size)
    cage = build_cage(low, args.cage, args.cage_twist) if args.cage else None

    # Exports (OBJ: Y up, forward -Z, the defaults; see the header).
    t0 = time.perf_counter()
    select_only(high)
    bpy.ops.wm.obj_export(filepath=os.path.join(out, "high.obj"), export_selected_objects=True,
                          export_uv=True, export_normals=True, export_materials=False,
                          export_triangulated_mesh=True, apply_modifiers=True)
    t["export_high_obj_s"] = time.perf_counter() - t0
    select_only(low)
    bpy.ops.wm.obj_export(filepath=os.path.join(out, "low.obj"), export_selected_objects=True,
                          export_uv=True, export_normals=True, export_materials=True,
                          export_triangulated_mesh=True, apply_modifiers=True)
    gltf = None
    try:
        bpy.ops.export_scene.gltf(filepath=os.path.join(out, "low.gltf"),
                                  export_format="GLTF_SEPARATE", use_selection=True,
                                  export_normals=True, export_texcoords=True,
                                  export_tangents=True, export_materials="NONE", export_yup=True)
        gltf = "low.gltf"
    except Exception as e:  # the add-on may be missing from a build
        print("glTF export failed:", e)
    if cage:
        select_only(cage)
        bpy.ops.wm.obj_export(filepath=os.path.join(out, "cage.obj"), export_selected_objects=True,
                              export_uv=True, export_normals=True, export_materials=False,
                              export_triangulated_mesh=True, apply_modifiers=True)

    # The bake.
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    scene.cycles.bake_type = "NORMAL"
    bake = scene.render.bake
    bake.normal_space = "TANGENT"
    bake.normal_r, bake.normal_g, bake.normal_b = "POS_X", "POS_Y", "POS_Z"
    bake.use_selected_to_active = True
    bake.use_cage = cage is not None
    if cage:
        bake.cage_object = cage
    bake.cage_extrusion = 0.0 if cage else args.extrusion
    bake.max_ray_distance = args.max_distance
    bake.margin = args.margin
    bake.margin_type = args.margin_type
    bake.target = "IMAGE_TEXTURES"
    bake.use_clear = False
    select_only(high, low)  # HIGH selected, LOW selected and active
    # Blender's own clear (use_clear) fills with (0.5, 0.5, 1, 1); filled by hand with alpha 0
    # instead, the bake's alpha shows which texels it wrote (islands, then margin).
    image.pixels.foreach_set(array.array("f", [0.5, 0.5, 1.0, 0.0]) * (args.size * args.size))

    t0 = time.perf_counter()
    result = bpy.ops.object.bake(
        type="NORMAL", normal_space="TANGENT", use_selected_to_active=True,
        use_cage=cage is not None, cage_object=cage.name if cage else "",
        cage_extrusion=0.0 if cage else args.extrusion, max_ray_distance=args.max_distance,
        margin=args.margin,
        margin_type=args.margin_type, use_clear=False, target="IMAGE_TEXTURES",
        save_mode="INTERNAL")
    t["bake_operator_s"] = time.perf_counter() - t0
    if "FINISHED" not in result:
        sys.exit("bake failed: %s" % (result,))

    # save_render with the scene's format, 8- then 16-bit RGBA (no dither; a Non-Color image gets
    # no view transform). (Image.save writes a float image as 16-bit too, but drops its alpha.)
    settings = scene.render.image_settings
    settings.file_format, settings.color_mode, settings.color_depth = "PNG", "RGBA", "8"
    settings.compression = 15
    scene.render.dither_intensity = 0.0
    t0 = time.perf_counter()
    image.save_render(os.path.join(out, "blender_normal.png"), scene=scene)
    t["save_png8_s"] = time.perf_counter() - t0
    settings.color_depth = "16"
    t0 = time.perf_counter()
    image.save_render(os.path.join(out, "blender_normal16.png"), scene=scene)
    t["save_png16_s"] = time.perf_counter() - t0

    info = {
        "blender_version": bpy.app.version_string,
        "timings": t,
        "high_triangles": triangles(high),
        "high_vertices": len(high.data.vertices),
        "low_triangles": triangles(low),
        "low_vertices": len(low.data.vertices),
        "size": args.size,
        "samples": args.samples,
        "cage_extrusion": 0.0 if cage else args.extrusion,
        "cage": {"offsets": args.cage, "twist": args.cage_twist} if cage else None,
        "max_ray_distance": args.max_distance,
        "margin": args.margin,
        "margin_type": args.margin_type,
        "high_subdiv": args.high_subdiv,
        "low": [segments, rings],
        "relief": {"amp": args.amp, "freq": args.freq,
                   "r": "1 + amp*cos(freq*x)*cos(freq*y)*cos(freq*z), (x,y,z) unit direction"},
        "threads": scene.render.threads,
        "cpu_count": os.cpu_count(),
        "gltf": gltf,
        "obj_axes": "Y up, forward -Z: OBJ (X,Y,Z) = Blender (x,z,-y)",
    }
    with open(os.path.join(out, "blender_timings.json"), "w") as f:
        json.dump(info, f, indent=2)
    print(json.dumps(info, indent=2))


main()

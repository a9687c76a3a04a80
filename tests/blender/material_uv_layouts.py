"""Headless Blender 3.4 test of the cloth material's frame on every UV
layout (garments lay their islands every way): islands laid with the face
winding, mirrored against it, rotated in UV space, laid clockwise, and
both orientations in one mesh, each against `clothbake lookup-render` of the same scene and
material. lookup-render's frame comes from the patch's dP/du and dP/dv,
so its weave's warp direction follows dP/dv on any layout; the material in
Blender must too (B = s N x T, s the UV map's handedness: material_nodes).

One small twill material (twill_2_1 of the paper cloth, blue weft: its
diagonal and its two colours show a mirrored frame) baked from a flat
cloth. Each case is a mesh made as an artist makes one: a Grid primitive
(its UVs scaled -1, rotated 90 degrees, or both, in place), a half Grid
under a Mirror modifier with Mirror U (a symmetric garment: one half's
UVs mirrored, both orientations in one evaluated mesh), an open Cylinder
primitive (a sleeve: curved, its inside seen as back faces) with its UVs
mirrored. The scene goes out through the add-on's exporter (the evaluated
mesh, so the Mirror modifier's half is in it) for lookup-render; the same
Blender scene is rendered in Cycles on the exact route (two seeds), and
the mixed mesh in Eevee too.

Bounds as in material_routes.py: the render's noise sigma from two seeds
(Eevee: SPP against 2 SPP samples), the reference's taken as the same;
a case passes when its relative RMSE is at most 3 sqrt(2) sigma plus the
stated systematic part (the dense light grid and the rank kept against
lookup-render's full lookup; Eevee's float16 textures and hashed alpha),
at full resolution and over 4 x 4 blocks. With the old frame (B = N x T
everywhere) the mirrored cases measured 3 to 6 times their bound.

Then the stretched cases (stretched()): a Grid scaled
3 x in x with its UVs kept, the open Cylinder as unwrapped, a Grid with
one island's UVs scaled 0.25, at a 6 x finer weave, each against its
bounds as above, with the level from each face's scale (the attribute
Apply writes) against the mean (that attribute removed), and with the
directions carried into the material's frame by each face's per-axis
scale (the frame-scale attribute) against without it (removed too: the
old group's directions), which must err at least twice as much over
4 x 4 blocks.

    blender -b --factory-startup --python-exit-code 1 -P material_uv_layouts.py -- \
        CLOTHBAKE_EXE SOURCE_DIR WORK_DIR
"""
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lib.checks import check, run_checks  # noqa: E402
from lib.headless import SOURCE, TMP, enable_addon  # noqa: E402
from lib.images import pixels, rel_rmse, render_still  # noqa: E402
from lib.noise import Noisy, blocks, within_noise  # noqa: E402
from lib.program import run  # noqa: E402
from lib.scene import lit_flat_scene  # noqa: E402

SPP = 32
REPEATS = 12    # per UV on the 2 x 2 flat cloth the material is baked from
SYS = 0.01
SYS_EEVEE = 0.015
FINE = 6        # the stretched cases' repeats per UV, times the others' (finer weave:
                # the pixel spans texels, so the level matters)
ISLAND_SCALE = 0.25

BASE = lit_flat_scene(SPP)


def against_winding(obj):
    """The fraction of the evaluated mesh's triangles whose UVs run against
    the face winding (UV signed area < 0 seen from the face normal)."""
    dg = bpy.context.evaluated_depsgraph_get()
    ob = obj.evaluated_get(dg)
    mesh = ob.to_mesh()
    try:
        mesh.calc_loop_triangles()
        uv = mesh.uv_layers.active.data
        neg = 0
        for tri in mesh.loop_triangles:
            t = [uv[i].uv for i in tri.loops]
            a = (t[1] - t[0]).cross(t[2] - t[0])
            neg += a < 0
        return neg / max(1, len(mesh.loop_triangles))
    finally:
        ob.to_mesh_clear()


# --- the meshes, made with Blender's own tools ---------------------------------

def grid():
    """The Grid primitive, 2 x 2, 8 x 8 quads, its UVs as generated."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=2.0,
                                    calc_uvs=True)
    return bpy.context.active_object


def transform_uvs(obj, f, faces=None):
    """UV' = f(UV) about the island's centre (0.5, 0.5) on `faces` (all
    when None): the UV editor's Scale -1 / Rotate 90, done on the data."""
    mesh = obj.data
    uv = mesh.uv_layers.active.data
    for poly in mesh.polygons:
        if faces is not None and poly.index not in faces:
            continue
        for li in poly.loop_indices:
            u, v = uv[li].uv
            uv[li].uv = [c + 0.5 for c in f(u - 0.5, v - 0.5)]


def half_grid_mirrored():
    """Half a Grid (x in [0, 1], 4 x 8 quads, scaled in Object Mode and the
    scale applied; its UVs squared up); mirror_modifier adds the other half."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=8, size=2.0,
                                    calc_uvs=True)
    obj = bpy.context.active_object
    obj.location = (0.5, 0.0, 0.0)
    obj.scale = (0.5, 1.0, 1.0)
    bpy.ops.object.transform_apply(location=True, rotation=False, scale=True)
    square_up(obj)
    return obj


def mirror_modifier(obj):
    """A Mirror modifier on X as a symmetric garment is modelled: the
    mirrored half shares the UVs (Mirror U off), so its island runs against
    its (reversed) winding."""
    mod = obj.modifiers.new("mirror", "MIRROR")
    mod.use_axis = (True, False, False)


def sleeve():
    """An open Cylinder primitive lying along x (a sleeve), 16 sides, its
    UVs squared up."""
    obj = sleeve_unwrapped()
    square_up(obj)
    return obj


def square_up(obj):
    """Scales the UVs in V about their centre so that a UV unit spans as
    much surface along V as along U (the UV editor's Scale Y that takes the
    stretch out): the material picks its level from the mean world units
    per UV, and a weave stretched one way only is a different test."""
    mesh = obj.data
    mesh.calc_loop_triangles()
    uv = mesh.uv_layers.active.data
    su = sv = 0.0
    for tri in mesh.loop_triangles:
        p = [mesh.vertices[i].co for i in tri.vertices]
        t = [uv[i].uv for i in tri.loops]
        e1, e2 = p[1] - p[0], p[2] - p[0]
        d1, d2 = t[1] - t[0], t[2] - t[0]
        det = d1.x * d2.y - d1.y * d2.x
        if abs(det) < 1e-12:
            continue
        dpdu = (e1 * d2.y - e2 * d1.y) / det
        dpdv = (e2 * d1.x - e1 * d2.x) / det
        su += dpdu.length * tri.area
        sv += dpdv.length * tri.area
    k = sv / su
    vs = [uv[i].uv.y for i in range(len(uv))]
    mid = 0.5 * (min(vs) + max(vs))
    for d in uv:
        d.uv.y = mid + (d.uv.y - mid) * k


def stretched_grid():
    """A Grid scaled 3 x in x in Object Mode, the scale applied, its UVs
    kept: every face stretched the same way (local scale = mean)."""
    obj = grid()
    obj.scale = (3.0, 1.0, 1.0)
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    return obj


def sleeve_unwrapped():
    """The open Cylinder primitive as unwrapped (no square-up)."""
    bpy.ops.mesh.primitive_cylinder_add(vertices=16, radius=0.45, depth=1.8,
                                        end_fill_type="NOTHING", calc_uvs=True,
                                        rotation=(0.0, math.pi / 2, 0.0), location=(0, 0, 0.2))
    obj = bpy.context.active_object
    bpy.ops.object.transform_apply(location=True, rotation=True, scale=True)
    return obj


def uneven_islands():
    """A Grid whose left half's UVs are scaled by ISLAND_SCALE about their
    own centre (the UV editor's Scale on one island): the weave is
    1 / ISLAND_SCALE times coarser there, the mean scale fits neither half."""
    obj = grid()
    mesh = obj.data
    uv = mesh.uv_layers.active.data
    left = [p for p in mesh.polygons if p.center.x < 0.0]
    for poly in left:
        for li in poly.loop_indices:
            u, v = uv[li].uv
            uv[li].uv = (0.25 + (u - 0.25) * ISLAND_SCALE, 0.5 + (v - 0.5) * ISLAND_SCALE)
    return obj


def mirror_u(u, v):
    return -u, v


def rotate_90(u, v):
    return -v, u


def clockwise_rotated(u, v):      # rotate 90, then mirror: the transpose
    return v, u


def main():
    enable_addon()
    from clothbake.blender.render_engines import use_eevee
    from clothbake.blender.material_apply import apply_material, world_per_uv
    from clothbake.blender.scene_export_bpy import export_scene
    from clothbake.blender.scene_import import import_scene

    cloth = json.load(open(os.path.join(SOURCE, "testscenes", "paper", "cloth.json")))
    cloth.update(name="twill", weave={"pattern": "twill_2_1"})
    cloth["weft"]["color"] = [0.15, 0.35, 0.6]
    cloth_path = os.path.join(TMP, "twill.json")
    with open(cloth_path, "w") as f:
        json.dump(cloth, f, indent=1)
    flat = os.path.join(TMP, "flat.obj")
    with open(flat, "w") as f:
        f.write("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                "f 1/1 2/2 3/3 4/4\n")
    base = dict(BASE, name="uv_base",
                objects=[{"name": "cloth", "mesh": flat, "cloth": cloth_path,
                          "repeats_per_uv": REPEATS, "thickness_world": 0.06,
                          "extinction_per_mm": 40}])
    base_path = os.path.join(TMP, "base.json")
    with open(base_path, "w") as f:
        json.dump(base, f, indent=1)
    material = os.path.join(TMP, "material")
    run(["material", base_path, "-o", material, "--texels", "16", "--directions", "8",
         "--light-directions", "6", "--spp", "1", "--quiet"])

    # The imported cloth keeps its settings (cloth, repeats, thickness);
    # each case puts a new mesh into it.
    (obj,) = import_scene(base_path, clear=True, samples=SPP)
    scene = bpy.context.scene

    cases = [
        ("with the winding (Grid as made)", grid, None, 0.0),
        ("mirrored: UVs scaled -1 in U", grid, mirror_u, 1.0),
        ("rotated 90 degrees in UV", grid, rotate_90, 0.0),
        ("laid clockwise: rotated 90 and mirrored", grid, clockwise_rotated, 1.0),
        ("both orientations: half Grid and a Mirror modifier", half_grid_mirrored,
         None, 0.5),
        ("sleeve: open Cylinder, UVs mirrored", sleeve, "mirror", None),
    ]
    table = []
    for i, (what, make, uv_f, expect) in enumerate(cases):
        made = make()
        old_mesh, obj.data = obj.data, made.data
        bpy.data.objects.remove(made)
        bpy.data.meshes.remove(old_mesh)
        obj.modifiers.clear()
        if make is half_grid_mirrored:
            mirror_modifier(obj)
        if uv_f == "mirror":
            # A sleeve as unwrapped runs with its winding; mirror it against.
            before = against_winding(obj)
            transform_uvs(obj, mirror_u if before < 0.5 else (lambda u, v: (u, v)))
        elif uv_f is not None:
            transform_uvs(obj, uv_f)
        frac = against_winding(obj)
        # The weave's depth scale must stay the material's (lookup-render
        # refuses 5 % off): repeats per UV follow the mesh's world per UV.
        scale = world_per_uv(obj, obj.data.uv_layers.active.name,
                             bpy.context.evaluated_depsgraph_get())
        obj.clothbake.repeats_per_uv = REPEATS * scale / 2.0
        print(f"{what}: {scale:.4g} world units per UV")
        if expect is not None:
            check(abs(frac - expect) < 0.02, f"{what}: {frac:.0%} of the triangles' UVs run "
                                             f"against the winding (expected {expect:.0%})")
        else:
            check(frac > 0.98, f"{what}: {frac:.0%} of the triangles' UVs run against the "
                               "winding")
        path = export_scene(scene, os.path.join(TMP, f"case{i}", "scene.json"))
        ref_path = os.path.join(TMP, f"ref{i}.exr")
        run(["lookup-render", path, material, "-o", ref_path, "--spp", str(2 * SPP),
             "--quiet"])
        ref = pixels(ref_path)
        apply_material(obj, material, route="exact")
        scene.render.engine = "CYCLES"
        a = render_still(os.path.join(TMP, f"case{i}_s1.exr"), 1)
        b = render_still(os.path.join(TMP, f"case{i}_s2.exr"), 2)
        errs = within_noise(f"Cycles, {what}", Noisy(a, b), ref, SYS)
        row = [what, frac, errs]
        if make is half_grid_mirrored:
            use_eevee(scene, SPP)
            ea = render_still(os.path.join(TMP, f"case{i}_eevee.exr"), 1)
            use_eevee(scene, 2 * SPP)
            eb = render_still(os.path.join(TMP, f"case{i}_eevee2.exr"), 1)
            row.append(within_noise(f"Eevee, {what}", Noisy(ea, eb, math.sqrt(1.5)), ref,
                               SYS_EEVEE))
            scene.render.engine = "CYCLES"
        table.append(row)
    print("case | against winding | Cycles px (bound) | 4x4 (bound) | Eevee px (bound)")
    for row in table:
        (e, eb), (e4, eb4) = row[2]
        extra = f" | {row[3][0][0]:.4f} ({row[3][0][1]:.4f})" if len(row) > 3 else ""
        print(f"{row[0]} | {row[1]:.0%} | {e:.4f} ({eb:.4f}) | {e4:.4f} ({eb4:.4f}){extra}")
    stretched(obj, scene, material, apply_material, world_per_uv, export_scene)


def put_mesh(obj, made):
    old_mesh, obj.data = obj.data, made.data
    bpy.data.objects.remove(made)
    bpy.data.meshes.remove(old_mesh)
    obj.modifiers.clear()


def face_scales(obj):
    attr = obj.data.attributes["clothbake_world_per_uv"]
    values = np.empty(len(attr.data), np.float32)
    attr.data.foreach_get("value", values)
    return values


def subsurf_carries(obj):
    """A Subdivision Surface after Apply: the evaluated mesh carries the
    face attribute (each face's value on its sub-faces)."""
    values = face_scales(obj)
    mod = obj.modifiers.new("subsurf", "SUBSURF")
    mod.levels = mod.render_levels = 1
    dg = bpy.context.evaluated_depsgraph_get()
    ob = obj.evaluated_get(dg)
    mesh = ob.to_mesh()
    try:
        attr = mesh.attributes.get("clothbake_world_per_uv")
        got = np.empty(len(attr.data) if attr else 0, np.float32)
        if attr:
            attr.data.foreach_get("value", got)
        check(attr is not None and attr.domain == "FACE" and len(got) == 4 * len(values)
              and set(np.unique(got)) == set(np.unique(values)),
              f"Subdivision Surface: the evaluated mesh's {len(got)} faces carry the "
              f"attribute ({sorted(set(np.unique(got).tolist()))})")
    finally:
        ob.to_mesh_clear()
        obj.modifiers.remove(mod)


def stretched(obj, scene, material, apply_material, world_per_uv, export_scene):
    """The stretched cases: the level from the UV map's local scale (the face
    attribute Apply writes) against the mean (the attribute removed: the
    group falls back to its World per UV input, the old behaviour). A finer
    weave (FINE x the repeats, the thickness / FINE: the same depth scale)
    so that a pixel spans several texels and the level matters."""
    cases = [
        ("Grid scaled 3 x in x, UVs kept", stretched_grid, False),
        ("open Cylinder as unwrapped", sleeve_unwrapped, False),
        (f"Grid, one island's UVs scaled {ISLAND_SCALE:g}", uneven_islands, True),
    ]
    table = []
    for i, (what, make, uneven) in enumerate(cases):
        put_mesh(obj, make())
        dg = bpy.context.evaluated_depsgraph_get()
        mean = world_per_uv(obj, obj.data.uv_layers.active.name, dg)
        # the depth scale lookup-render checks is the mean over quads of the
        # local scale (the faces' attribute): repeats follow it
        from clothbake.blender.material_apply import write_face_world_per_uv
        write_face_world_per_uv(obj, obj.data.uv_layers.active.name)
        local = face_scales(obj)
        obj.clothbake.repeats_per_uv = FINE * REPEATS * float(local.mean()) / 2.0
        obj.clothbake.thickness_world = 0.06 / FINE
        spread = float(local.max() / local.min())
        print(f"{what}: mean {mean:.4g} world units per UV, faces {local.min():.4g} to "
              f"{local.max():.4g}")
        check((spread > 3.0) if uneven else (spread < 1.001),
              f"{what}: local scales span x {spread:.3f}")
        path = export_scene(scene, os.path.join(TMP, f"stretch{i}", "scene.json"))
        ref_path = os.path.join(TMP, f"stretch_ref{i}.exr")
        run(["lookup-render", path, material, "-o", ref_path, "--spp", str(2 * SPP), "--quiet"])
        ref = pixels(ref_path)
        apply_material(obj, material, route="exact")
        scene.render.engine = "CYCLES"
        a = render_still(os.path.join(TMP, f"stretch{i}_s1.exr"), 1)
        b = render_still(os.path.join(TMP, f"stretch{i}_s2.exr"), 2)
        noisy = Noisy(a, b)
        errs = within_noise(f"Cycles, {what}", noisy, ref, SYS)
        obj.data.attributes.remove(obj.data.attributes["clothbake_world_per_uv"])
        o = render_still(os.path.join(TMP, f"stretch{i}_mean.exr"), 1)
        old = [(rel_rmse(ref, o), errs[0][1]), (rel_rmse(blocks(ref), blocks(o)), errs[1][1])]
        frame_scale = obj.data.attributes["clothbake_frame_scale"]
        saved = np.empty(len(frame_scale.data) * 3, np.float32)
        frame_scale.data.foreach_get("vector", saved)
        obj.data.attributes.remove(frame_scale)
        d = render_still(os.path.join(TMP, f"stretch{i}_dirs.exr"), 1)
        dirs = rel_rmse(blocks(ref), blocks(d))
        check(dirs > 2.0 * errs[1][0], f"{what}: without the per-face frame scale the 4x4 "
              f"error is {dirs:.4f}, over twice its {errs[1][0]:.4f}")
        restored = obj.data.attributes.new("clothbake_frame_scale", "FLOAT_VECTOR", "FACE")
        restored.data.foreach_set("vector", saved)
        if uneven:
            check(errs[0][0] < old[0][0], f"{what}: per pixel the local scale errs less "
                  f"({errs[0][0]:.4f}) than the mean ({old[0][0]:.4f}), same seed")
            write_face_world_per_uv(obj, obj.data.uv_layers.active.name)
            subsurf_carries(obj)
        else:
            check(np.array_equal(o, a), f"{what}: local = mean, the renders identical")
        table.append((what, old, errs, dirs))
        obj.modifiers.clear()
    print("stretched case | mean scale: px / 4x4 | local scale: px / 4x4 | bounds px / 4x4 | "
          "no frame scale: 4x4")
    for what, old, new, dirs in table:
        print(f"{what} | {old[0][0]:.4f} / {old[1][0]:.4f} | {new[0][0]:.4f} / {new[1][0]:.4f} "
              f"| {new[0][1]:.4f} / {new[1][1]:.4f} | {dirs:.4f}")


run_checks(main)

"""The render engines' identifiers and settings across the Blenders the
add-on supports (3.4 to 5.x), stated once.

Eevee's identifier moved with its rewrite: `BLENDER_EEVEE` up to 4.1, the
rewrite ("Eevee Next") `BLENDER_EEVEE_NEXT` from 4.2 to 4.x, and
`BLENDER_EEVEE` again from 5.0, where the old Eevee is gone. Eevee Next also
dropped the screen-space effects the legacy Eevee had as switches (bloom,
screen-space reflections; ambient occlusion became part of its ray tracing),
so those are turned off only where the switch exists."""
import bpy


def eevee_engine_id():
    """The identifier of Eevee in this Blender: the one of the render
    engines it lists whose name begins with BLENDER_EEVEE."""
    engines = [item.identifier for item in
               bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items]
    for engine_id in ("BLENDER_EEVEE_NEXT", "BLENDER_EEVEE"):
        if engine_id in engines:
            return engine_id
    raise RuntimeError(f"this Blender lists no Eevee engine ({', '.join(engines)})")


def use_eevee(scene, samples):
    """Eevee set up like scene_import's Cycles: the same film, box filter
    one pixel wide, `samples` anti-aliasing samples, no screen-space effects
    that clothbake's renderer does not have."""
    scene.render.engine = eevee_engine_id()
    e = scene.eevee
    e.taa_render_samples = samples
    for switch in ("use_gtao", "use_bloom", "use_ssr", "use_raytracing"):
        if hasattr(e, switch):
            setattr(e, switch, False)
    scene.render.filter_size = 1.0

"""Step 5: per light (and, on the cycles-lit route, the world) its
direction and irradiance at the shading point and the address of its light
factors."""
import math

from ..running_units import RUNNING_UNITS as UNITS
from ...core.material_manifest import HORIZON
from .common import BLACK, LightTerm, mix
from .directions import hemi_octahedral, horizon_warp, pick_node, to_frame
from .frame import frame_scaled


def _spot_mask(g, gin, l, direction, col):
    """Cycles' spot attenuation in this Blender (core/light_units.py): a =
    cos(angle between the light's axis and the way to the point), smoothstep(
    (a - cos(size / 2)) / smooth), 0 outside the cone; smooth = (1 - cos(size
    / 2)) x blend, 0 for a hard edge. Up to 3.x the mask is a times that
    (measured in 3.4); from 4.0 it is the smoothstep alone (4.3, 5.2)."""
    a = g.math("MULTIPLY", g.vmath("DOT_PRODUCT", direction, gin[f"Light {l} axis"],
                                   column=col), -1.0, column=col)
    t = g.math("DIVIDE", g.math("SUBTRACT", a, gin[f"Light {l} cos half angle"], column=col),
               g.math("MAXIMUM", gin[f"Light {l} smooth"], 1e-9, column=col), column=col,
               clamp=True)
    smooth = g.math("MULTIPLY", g.math("MULTIPLY", t, t, column=col),
                    g.math("MULTIPLY_ADD", t, -2.0, 3.0, column=col), column=col)
    return g.math("MULTIPLY", a, smooth, column=col) if UNITS.spot_axis_cosine else smooth


def _area_offset(g, gin, l, xis, col):
    """A point on area light l, uniform over its shape, from two random
    numbers (shifted per light), as its offset from the centre: su U + sv V
    with U, V its sides; (su, sv) in the square [-1/2, 1/2]^2, or in the
    disk of radius 1/2 (r = sqrt(xi) / 2, angle 2 pi xi') when the ellipse
    flag is 1. The pixel's samples hit other points, so they integrate the
    light."""
    xa = g.math("FRACT", g.math("ADD", xis[0], (0.6180339887 * l) % 1.0, column=col), column=col)
    xb = g.math("FRACT", g.math("ADD", xis[1], (0.4142135624 * l) % 1.0, column=col), column=col)
    r = g.math("MULTIPLY", g.math("SQRT", xa, column=col), 0.5, column=col)
    phi = g.math("MULTIPLY", xb, 2.0 * math.pi, column=col)
    ellipse = gin[f"Light {l} ellipse"]
    su = g.lerp(g.math("SUBTRACT", xa, 0.5, column=col), g.math(
        "MULTIPLY", r, g.math("COSINE", phi, column=col), column=col), ellipse, col)
    sv = g.lerp(g.math("SUBTRACT", xb, 0.5, column=col), g.math(
        "MULTIPLY", r, g.math("SINE", phi, column=col), column=col), ellipse, col)
    on_u = g.scale(gin[f"Light {l} side u"], su, col)
    on_v = g.scale(gin[f"Light {l} side v"], sv, col)
    return g.vmath("ADD", on_u, on_v, column=col)


def _light_at(g, gin, l, kind, position, target, col):
    """The unit direction toward light l and the factor its irradiance input
    is scaled by at the point: a sun's 1; a point light's 1 / r^2; a spot's
    1 / r^2 x its cone's attenuation; an area light's cos(off its normal) /
    r^2 toward `target`, a point on it (0 behind it: one-sided), whose
    irradiance input is its radiant intensity along the normal."""
    vec, is_point = gin[f"Light {l} vector"], gin[f"Light {l} point"]
    if kind in ("SUN", "POINT"):
        to_point = g.vmath("SUBTRACT", vec, position, column=col)
        direction = g.vmath("NORMALIZE", g.vmath("ADD", vec, g.scale(g.vmath(
            "SUBTRACT", to_point, vec, column=col), is_point, col), column=col), column=col)
        r2 = g.math("MAXIMUM", g.vmath("DOT_PRODUCT", to_point, to_point, column=col), 1e-12,
                    column=col)
        atten = g.math("ADD", g.math("MULTIPLY", is_point, g.math("SUBTRACT", g.math(
            "DIVIDE", 1.0, r2, column=col), 1.0, column=col), column=col), 1.0, column=col)
        return direction, atten
    to_point = g.vmath("SUBTRACT", vec if kind == "SPOT" else target, position, column=col)
    direction = g.vmath("NORMALIZE", to_point, column=col)
    inv_r2 = g.math("DIVIDE", 1.0, g.math("MAXIMUM", g.vmath(
        "DOT_PRODUCT", to_point, to_point, column=col), 1e-12, column=col), column=col)
    if kind == "SPOT":
        return direction, g.math("MULTIPLY", inv_r2, _spot_mask(g, gin, l, direction, col),
                                 column=col)
    cos_light = g.math("MAXIMUM", g.math("MULTIPLY", g.vmath(
        "DOT_PRODUCT", direction, gin[f"Light {l} axis"], column=col), -1.0, column=col), 0.0,
        column=col)
    return direction, g.math("MULTIPLY", inv_r2, cos_light, column=col)


def _light(g, gin, l, kind, frame, position, view, light_map, pack, lit, xis, col,
           target=None, weight=1.0):
    """Step 5 for light l (for an area light, the point `target` on it,
    `weight` its share): its direction and irradiance at the point and its
    light factors' address. Returns (LightTerm, the cycles-lit
    denominator's term E cos, or None on route exact)."""
    vi, view_row = view
    m = pack.dense
    q = m + 2
    irr = gin[f"Light {l} irradiance"]
    direction, atten = _light_at(g, gin, l, kind, position, target, col)
    if weight != 1.0:
        atten = g.math("MULTIPLY", atten, weight, column=col)
    irradiance = mix(g, "ADD", BLACK, irr, atten, col)
    lx, ly, lz = to_frame(g, frame, direction, col + 1)
    light_side = g.math("LESS_THAN", lz, 0.0, column=col + 1)
    lu, lv = hemi_octahedral(g, *frame_scaled(g, frame, lx, ly, lz, col + 1), col + 1)
    if light_map == HORIZON:
        lu, lv = horizon_warp(g, lu, lv, col + 2)
    la = pick_node(g, lu, m, xis[0], col + 3)
    lb = pick_node(g, lv, m, xis[1], col + 3)
    # tile of (view_side, i, j), group 0, light side; pixel centre of (a, b)
    lpx = g.math("ADD", g.math("MULTIPLY", g.math("MULTIPLY_ADD", vi, 2.0, light_side,
                                                  column=col + 4), float(q), column=col + 4),
                 g.math("ADD", la, 1.5, column=col + 4), column=col + 4)
    lpy = g.math("ADD", g.math("MULTIPLY", view_row, float(q), column=col + 4),
                 g.math("ADD", lb, 1.5, column=col + 4), column=col + 4)
    luv = g.combine(g.math("DIVIDE", lpx, float(pack.light_width), column=col + 5),
                    g.math("DIVIDE", lpy, float(pack.light_height), column=col + 5), 0.0,
                    column=col + 5)
    if not lit:
        return LightTerm(luv, [(irradiance, 0)]), None
    cos_l = g.vmath("DOT_PRODUCT", direction, frame.facing, column=col + 5)
    front = g.math("GREATER_THAN", cos_l, 0.0, column=col + 5)
    e_front = mix(g, "ADD", BLACK, irradiance, front, col + 5)
    e_back = mix(g, "SUBTRACT", irradiance, e_front, 1.0, col + 5)
    term = mix(g, "ADD", BLACK, e_front, g.math("MAXIMUM", cos_l, 0.0, column=col + 5), col + 5)
    return LightTerm(luv, [(e_front, 0), (e_back, 1)]), term


def light_terms(g, gin, frame, position, view, info, pack, kinds, lit, xis, col):
    """Step 5 for every light: ([LightTerm], cycles-lit denominator or
    None, the next free column)."""
    per_light, denom = [], None
    for l, kind in enumerate(kinds):
        targets = [None]
        if kind == "AREA":
            # Two points on it, mirrored through its centre (antithetic:
            # the light's fall-off across it cancels to first order), each
            # weighted 1/2.
            offset = _area_offset(g, gin, l, xis[2:], col)
            centre = gin[f"Light {l} vector"]
            targets = [g.vmath("ADD", centre, offset, column=col),
                       g.vmath("SUBTRACT", centre, offset, column=col)]
        for target in targets:
            light, term = _light(g, gin, l, kind, frame, position, view, info.light_map, pack,
                                 lit, xis, col, target=target, weight=1.0 / len(targets))
            per_light.append(light)
            if term is not None:
                denom = term if denom is None else mix(g, "ADD", denom, term, 1.0, col + 6)
            col += 7
    return per_light, denom, col


def world_terms(g, gin, view, pack, k, col):
    """Step 5 for the world, on the cycles-lit route: a uniform world of
    radiance W adds W sum_k C_k G_k(v), G the light factors integrated over
    a hemisphere (material_pack's world factors), G over the viewer's
    hemisphere into the front sum (so the Diffuse closure, lit by Cycles'
    own world, carries it) and over the other into the sum from behind.
    Two LightTerms, read like a light's factors at the picked view node;
    and the cycles-lit denominator's world term pi W, the irradiance a
    uniform world gives a Lambertian closure over its open hemisphere.
    Returns ([LightTerm front, LightTerm behind], pi W)."""
    vi, view_row = view
    q = pack.dense + 2
    x = g.math("MULTIPLY_ADD", vi, 2.0 * q, 1.5, column=col)           # pixel centre, ws = 0
    y = g.math("ADD", view_row, 2.0 * k * q + 0.5, column=col)
    u = g.math("DIVIDE", x, float(pack.light_width), column=col)
    v = g.math("DIVIDE", y, float(pack.light_height), column=col)
    front = g.combine(u, v, 0.0, column=col)
    behind = g.combine(g.math("ADD", u, float(q) / pack.light_width, column=col), v, 0.0,
                       column=col)
    radiance = g.ready(gin["World radiance"], "RGBA")
    return [LightTerm(front, [(radiance, 0)]), LightTerm(behind, [(radiance, 1)])], \
        mix(g, "ADD", BLACK, radiance, math.pi, col)

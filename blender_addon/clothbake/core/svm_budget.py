"""How many lights the cloth material's node group can read before Cycles
runs out of its SVM stack.

Cycles compiles a shader's nodes into a program for its SVM (shader virtual
machine) that keeps every value on a stack of 255 floats until its last
reader has run. The material's group reads each light at every component
(docs/design/material.md, "Lights and the SVM stack"), so each light holds about
ten floats of that stack for the whole shader: past the limit Cycles prints
"out of SVM stack space, shader ... too big" and renders the cloth black,
with nothing in Blender's interface to say why. Eevee and Material Preview
compile GLSL instead (not measured this far). A hidden light is still read
(its driver zeroes it, so showing it again needs no new Apply), so only
lights removed from the scene lower the count.

The limits are measured, not derived (scripts/dev/svm_peak.sh, Cycles 3.4):
the paper scene with its lights replaced by N point lights, a
material of the paper cloth (R 16, K 12, KL 8, 1 sample), rank 24 evaluated
(the most the add-on evaluates). An area light is read at two points, so it
counts as two terms; a sun, a point light and a spot count one. On the
cycles-lit route the world's term (two reads per group of four components:
material_nodes.lights.world_terms) counts two as well: 12 point lights and
the world compiled at a peak of 244 floats, 13 and the world overflowed
(colour-free).
"""

# (colour-free parts?, route) -> the most light terms that still compile.
# Peak stack, colour-free, exact: 60 floats at 1 term, 130 at 8, 167 at 12,
# 207 at 16, 246 at 20, overflow at 21; cycles-lit 253 at 14, overflow at
# 15. RGB: exact 230 at 20, cycles-lit 226 at 14, and overflow at 21 and 15
# all the same. lab/svm_limits/svm_limits.sh measures every edge again.
LIGHT_TERM_LIMIT = {
    (True, "exact"): 20,
    (True, "cycles-lit"): 14,
    (False, "exact"): 20,
    (False, "cycles-lit"): 14,
}


# Blender 5.x inlines node groups before Cycles compiles them, and the same
# group then holds far more of the stack: the default paper material
# (R 32, K 16, KL 10, colour-free) with two point lights compiles to 5079
# SVM nodes at a peak of 187 floats in 5.2.2, against 1453 nodes and 72 in
# 3.4.1 and 4.3.2 (scripts/dev/svm_peak.sh in each). Measured in 5.2.2 with
# that material and N point lights: exact 10 lights at 240, 12 overflowed;
# cycles-lit overflowed with one light and the world (a small material,
# R 16, K 6, KL 6, compiles with two). None: no count is known to compile,
# and Apply material cautions on every cycles-lit group.
LIGHT_TERM_LIMIT_5 = {
    (True, "exact"): 11,
    (True, "cycles-lit"): None,
    (False, "exact"): 11,
    (False, "cycles-lit"): None,
}


def term_limit(colour_free, route, blender_version=(3, 4, 0)):
    """The most light terms that compile for the route in this Blender
    (None: none does)."""
    table = LIGHT_TERM_LIMIT_5 if tuple(blender_version[:2]) >= (5, 0) else LIGHT_TERM_LIMIT
    return table[(bool(colour_free), route)]


# The world's terms per route: cycles-lit reads the world's factors twice.
WORLD_TERMS = {"exact": 0, "cycles-lit": 2}


def light_terms(kinds, route="exact"):
    """The light terms of the group for `kinds` (material_nodes.light_kinds:
    "POINT" for a sun or a point light, "SPOT", "AREA") on `route`, the
    world's included."""
    return sum(2 if k == "AREA" else 1 for k in kinds) + WORLD_TERMS[route]


def stack_note(kinds, colour_free, route, blender_version=(3, 4, 0)):
    """Apply material's note when the lights are past the measured limit of
    the route in this Blender (LIGHT_TERM_LIMIT up to 4.x,
    LIGHT_TERM_LIMIT_5 from 5.0), else None."""
    terms = light_terms(kinds, route)
    limit = term_limit(colour_free, route, blender_version)
    if limit is None:
        return (f"in Blender {blender_version[0]}.{blender_version[1]} the {route} route "
                "overflows Cycles' shader stack for a material of the default size under a "
                "single light (measured in 5.2); if the cloth renders black and the console "
                "says 'out of SVM stack space', use the exact route "
                "(docs/design/material.md, 'Lights and the SVM stack')")
    if terms <= limit:
        return None
    areas = sum(1 for k in kinds if k == "AREA")
    counted = [f"an area light counts two: {areas} of them"] if areas else []
    if WORLD_TERMS[route]:
        counted.append(f"the world counts {WORLD_TERMS[route]}")
    counted = f" ({'; '.join(counted)})" if counted else ""
    return (f"{len(kinds)} lights make {terms} light terms{counted}: past {limit} on the "
            f"{route} route Cycles runs out of its shader stack ('out of SVM stack space' "
            "in the console) and renders the cloth black; delete lights the cloth can do "
            "without (hidden ones still count) and Apply material again "
            "(docs/design/material.md, 'Lights and the SVM stack')")

"""The cloth material's node group (docs/formats/material.md), plain nodes
that Cycles, Eevee and the viewport's Material Preview all run. Nothing is
stored per face but the UV map's local scale (an attribute read for the
level). Per shading point the group computes, one module a step (build.py
runs them in this order):
  1. frame.py, the frame (shading_frame): N the true normal (Geometry's, unflipped with
     Backfacing), T the UV map's tangent made orthogonal to N, B = s N x T
     with s = +-1 the UV map's handedness there (the sign of a Normal Map
     node's signed bitangent, below), so B follows dP/dv on islands laid
     against the face winding too;
     the directions toward the eye (view_direction) and toward each light
     (lights.py) in that frame, through directions.py's node maths;
  2. address.py, where in the repeat (texel_address): the UV map x repeats per UV, its
     fraction; for a material addressed per crossing (crossing_address),
     the crossing and the texel in it, each crossing S_L texels a side
     whatever its width, the tap's block read from the pack's per-crossing
     index (a Closest read), its colours a column a thread (colours.thread_places);
  3. level.py, the level from the pixel's footprint (footprint_level, below);
  4. view.py, the view node (view_node), level and texel, each picked at random with
     the probabilities of clothbake's bilinear / trilinear weights (a White
     Noise of the position, randoms: every sample of a pixel hits another
     point), so that one read of the Blender images
     (clothbake.core.material_pack) per component replaces 4 views x 2
     levels x 4 texels; the pixel's samples average the blend ("stochastic
     texture filtering"). Every image is read with Closest: nothing bleeds
     between tiles, and Eevee's GPU mip-maps (which an atlas cannot use)
     never come into play. A material baked with --view-parallax reads the
     picked view node shifted to where its ray meets the eye's at the
     material's fitted depth (parallax_shift; baker view_parallax.h);
  5. lights.py, per light (light_terms), its direction's light factors (resampled densely
     in the pack, so a stochastic bilinear read stands in for clothbake's
     Catmull-Rom), times its irradiance: W_k = sum_l E_l F_k(v, l). A sun's
     E is its input; a point light's over r^2; a spot's that times Cycles'
     cone mask; an area light is read at two points mirrored
     through its centre, picked at random on its shape, each
     a point light of half its intensity times cos(off its normal);
  6. components.py, L = max(0, sum_k C_k W_k), alpha A; the closures
     (shaders.py). A colour-free material (parts "specular-warp-weft") sums
     its five parts apart, S = sum_k S_k W_k and likewise W, F, Wn, Fn
     (each RGB: W_k is), and L = S + W c_warp + F c_weft + Wn c_warp_next
     + Fn c_weft_next (colours.py), the yarn colours read from the group's
     colour inputs or, per thread, from the colour strips
     (material_colours.py) at the texel step 4 picked, the
     next colours from the owner + 1 or - 1 strip as the picked view node's
     ray runs (the pack's next atlas holds that side): colours change with
     no rebuild, by the inputs' values and the strips' pixels.
Route "exact": Emission(L) + Transparent(1 - A), the reference renderer's
sum (no shadows from other objects, no cloth-on-cloth shadowing).
Route "cycles-lit": lights on the viewer's side of the surface go through
a Diffuse closure whose colour is pi L_front / (sum_l E_l cos_l + pi W), so
that Cycles (or Eevee) adds its own shadows and the light's live power;
lights behind the surface (light through the cloth) stay Emission. The
world, as a uniform radiance W (the World radiance input), is two more
terms read like a light's (lights.world_terms): the material's factors
integrated over the viewer's hemisphere into the closure's sum (pi W in its denominator:
Cycles lights the closure with the world itself), over the other into the
Emission.

The footprint: the distance to the camera (the point in camera space) x
the camera's pixel angle (sensor width / lens / pixels, a driver on the
scene's camera and resolution), stretched by 1 / sqrt(cos) of the view's
tilt, in level-0 texels through the world units per UV there: the face's
sqrt(world area / UV area), a FACE attribute Apply writes on the mesh
(clothbake's local frame takes the same geometric mean of the two axes);
where that attribute is missing or 0, the group's World per UV input (the
mean over the evaluated mesh). Divided by sqrt(samples)
(Cycles' samples: each sample prefilters its stratum of the pixel).

Node creation order matters, not only the graph: Cycles compiles nodes in
creation order and keeps a value on its 255-float SVM stack until its last
user, so the steps run in the order above and must not be reordered. The
group's sockets are sockets.py's; what the steps share, common.py's.
"""
from .build import GROUP_VERSION, build_group, layout_suffix, light_kinds
from .common import FRAME_SCALE_ATTRIBUTE, STRETCH_ATTRIBUTE, Strips

__all__ = ["FRAME_SCALE_ATTRIBUTE", "GROUP_VERSION", "STRETCH_ATTRIBUTE", "Strips", "build_group",
           "layout_suffix", "light_kinds"]

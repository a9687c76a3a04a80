"""Step 6's closures and the group's outputs."""
import math


def shaders(g, sums, alpha, denom, lit, col):
    """Step 6's closures into the group's outputs: Emission (+ Diffuse when
    lit) + Transparent(1 - A); Color the radiance, Alpha A. Every value
    first, then the closures, then the output (graph.Graph: creation
    order)."""
    radiance, radiance_back = sums
    zero = (0.0, 0.0, 0.0)
    front = radiance if radiance is not None else zero
    back = radiance_back if radiance_back is not None else zero
    if lit and radiance is not None and radiance_back is not None:
        # Cycles compiles the Diffuse closure's inputs, then the Emission's:
        # whatever both sums read (every coefficient) would wait on the SVM
        # stack between the two. max(f, min(b, 0)) makes the front sum read
        # the back one, so the Diffuse's inputs compute both, and the
        # max(., 0) below makes it max(f, 0) exactly.
        front = g.vmath("MAXIMUM", front, g.vmath("MINIMUM", back, zero, column=col + 4),
                        column=col + 4)
    radiance = g.vmath("MAXIMUM", front, zero, column=col + 4)
    transparency = g.ready(g.math("SUBTRACT", 1.0, alpha, column=col + 5, clamp=True), "RGBA")
    if lit:
        radiance_back = g.vmath("MAXIMUM", back, zero, column=col + 4)
        safe = g.vmath("MAXIMUM", denom if denom is not None else zero, (1e-6,) * 3,
                       column=col + 4)
        colour = g.ready(g.scale(g.vmath("DIVIDE", radiance, safe, column=col + 5), math.pi,
                                 col + 5), "RGBA")
        emitted = g.ready(radiance_back, "RGBA")
        color_out = g.ready(g.vmath("ADD", radiance, radiance_back, column=col + 5), "RGBA")
        diffuse = g.node("ShaderNodeBsdfDiffuse", col + 6)
        g.feed(diffuse.inputs["Color"], colour)
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], emitted)
        add1 = g.node("ShaderNodeAddShader", col + 7)
        g.feed(add1.inputs[0], diffuse.outputs[0])
        g.feed(add1.inputs[1], emission.outputs[0])
    else:
        color_out = g.ready(radiance, "RGBA")
        emission = g.node("ShaderNodeEmission", col + 6)
        g.feed(emission.inputs["Color"], color_out)
        add1 = emission
    transparent = g.node("ShaderNodeBsdfTransparent", col + 6)
    g.feed(transparent.inputs["Color"], transparency)
    add = g.node("ShaderNodeAddShader", col + 7)
    g.feed(add.inputs[0], add1.outputs[0])
    g.feed(add.inputs[1], transparent.outputs[0])
    out = g.node("NodeGroupOutput", col + 8)
    g.feed(out.inputs["Shader"], add.outputs[0])
    g.feed(out.inputs["Color"], color_out)
    g.feed(out.inputs["Alpha"], alpha)

"""Step 6: each component's coefficients times its light factors, summed
into the radiance (or, colour-free, into its five parts), in the order
Cycles' SVM stack allows."""
from ..graph import SubGraph
from .common import BLACK, mix


def _factor_reads(g, gi, per_light, light_image, k, pack, col, gate=None):
    """Each light's factors of components 4 gi .. 4 gi + 3: (R, G, B, A);
    the addresses times `gate` (_gated: exactly 1) when there is one."""
    q = pack.dense + 2
    factors = []
    for l, light in enumerate(per_light):
        offset = (gi * 2.0 * k * q / pack.light_width, 0.0, 0.0)
        if gate is None:
            at = g.vmath("ADD", light.uv, offset, column=col)
        else:
            uv = g.ready(light.uv, "VECTOR")
            n = g.node("ShaderNodeVectorMath", col, operation="MULTIPLY_ADD")
            g.feed(n.inputs[0], uv)
            g.feed(n.inputs[1], gate)
            g.feed(n.inputs[2], offset)
            at = n.outputs["Vector"]
        tex = g.node("ShaderNodeTexImage", col, image=light_image,
                     interpolation="Closest", extension="EXTEND",
                     label=f"light {l} factors {4 * gi}..{4 * gi + 3}")
        g.feed(tex.inputs["Vector"], at)
        r, gg, b = g.separate(tex.outputs["Color"], column=col + 1)
        factors.append((r, gg, b, tex.outputs["Alpha"]))
    return factors


def _component(g, kk, c, coeff_image, address, per_light, factors, sums, pack, col,
               next_image=None):
    """Component kk (channel c of its group's factors): its coefficients
    read, times each light's W_k, added into `sums`. Colour-free (a
    `next_image`): each of the five parts S, W, F (the coefficients' RGB)
    and Wn, Fn (the next atlas's R, G) times W_k into its own sum, [S, W,
    F, Wn, Fn] per accumulator. Returns the read's alpha output (and, when
    colour-free, the next atlas's sides: plus_x, plus_y)."""
    uv0, step = address[:2]
    where = uv0
    if kk:
        n = g.node("ShaderNodeVectorMath", col + 2, operation="MULTIPLY_ADD")
        g.feed(n.inputs[0], step)
        g.feed(n.inputs[1], (float(kk % pack.per_row), float(kk // pack.per_row), 0.0))
        g.feed(n.inputs[2], uv0)
        where = n.outputs["Vector"]
    tex = g.node("ShaderNodeTexImage", col + 3, image=coeff_image,
                 interpolation="Closest", extension="EXTEND", label=f"component {kk}")
    g.feed(tex.inputs["Vector"], where)
    weights = [None, None]
    for light, f in zip(per_light, factors):
        for e, which in light.parts:
            weights[which] = mix(g, "ADD", weights[which] or BLACK, e, f[c], col + 4)
    if next_image is not None:
        nxt = g.node("ShaderNodeTexImage", col + 3, image=next_image,
                     interpolation="Closest", extension="EXTEND", label=f"component {kk} next")
        g.feed(nxt.inputs["Vector"], where)
        s_, w_, f_ = g.separate(tex.outputs["Color"], column=col + 4)
        wn, fn, plus_x = g.separate(nxt.outputs["Color"], column=col + 4)
        for which in (0, 1):
            if weights[which] is not None:
                acc = sums[which] or [BLACK] * 5
                sums[which] = [mix(g, "ADD", a, weights[which], p, col + 5)
                               for a, p in zip(acc, (s_, w_, f_, wn, fn))]
        return tex.outputs["Alpha"], (plus_x, nxt.outputs["Alpha"])
    for which in (0, 1):
        if weights[which] is not None:
            term = mix(g, "MULTIPLY", tex.outputs["Color"], weights[which], 1.0, col + 5)
            sums[which] = term if sums[which] is None else \
                mix(g, "ADD", sums[which], term, 1.0, col + 5)
    return tex.outputs["Alpha"]


def _gated(g, last, address):
    """The group's texture coordinates (the address's uv0 and step; the
    factor reads take the gate as a vector, _factor_reads) times a gate
    that is exactly 1 but is read from
    `last`, the previous group's last coefficient read (1 - (a < -3e38):
    1 for any alpha, NaN included). Why: Cycles makes the conversion of a
    texture read's coordinates (a vector into the read's point socket)
    after every node of the sub-group, so each read waits a compile pass;
    ungated, every group's coordinates were computed in that pass and held
    on the SVM stack together (3 floats per read: 24 reads and three
    lights overflowed it). Gated, a group's coordinates are computed once
    the previous group's reads are done."""
    gate = g.math("MULTIPLY_ADD", g.math("LESS_THAN", last, -3e38, column=0), -1.0, 1.0,
                  column=0)
    uv0, step = address[:2]
    return ((g.scale(uv0, gate, 0), g.scale(step, gate, 0)) + tuple(address[2:]),
            g.scale((1.0, 1.0, 1.0), gate, 0))


def components(g, images, address, per_light, k, pack, col):
    """Step 6: per group of four components, each light's factors, then the
    four coefficients, summed at once. Nodes are made in this order because
    Cycles compiles them in creation order and keeps a value on its SVM
    stack (255 floats) until its last user: all W_k first, then all C_k,
    overflowed the stack at rank 24 on the cycles-lit route ("out of SVM
    stack space": a black cloth). Returns ([radiance (front when lit),
    radiance from behind], alpha, the next free column); colour-free
    (images holding a third, the next atlas): ([[S, W, F, Wn, Fn] per
    accumulator], alpha, the column, (plus_x, plus_y))."""
    coeff_image, light_image = images[:2]
    next_image = images[2] if len(images) > 2 else None
    sums = [None, None]
    alpha = sides = last = None
    for gi in range(pack.groups):
        # Each group of four in a sub-group of its own (graph.SubGraph: the
        # build's cost), made where its nodes stood, so the order holds.
        sub = SubGraph(g, f".{g.tree.name} components {4 * gi}-{4 * gi + 3}", col)
        group_address, gate = address, None
        if last is not None:
            group_address, gate = _gated(sub, last, address)
        firsts, spare = [], []
        factors = _factor_reads(sub, gi, per_light, light_image, k, pack, 0, gate)
        for c in range(4):
            kk = 4 * gi + c
            if kk >= pack.rank:
                break
            a = _component(sub, kk, c, coeff_image, group_address, per_light, factors, sums,
                           pack, 0, next_image)
            if next_image is not None:
                a, side = a
                if kk == 0:
                    firsts += list(side)
                else:
                    spare.append(side[0])
            if kk == 0:
                firsts.insert(0, a)
            read_alpha = a
        # The next gate's source: the last read's alpha, and the next
        # atlas's plus_x of components past 0 (a copy of component 0's):
        # Cycles' Separate Color keeps an output nobody reads on the SVM stack
        # to the end, so each is read here (min), 1 float a component.
        for plus in spare:
            read_alpha = sub.math("MINIMUM", read_alpha, plus, column=0)
        flat = [s for acc in sums if acc is not None for s in (acc if isinstance(acc, list) else [acc])]
        outs = sub.finish(flat + firsts + [read_alpha])
        it = iter(outs)
        sums = [None if acc is None else ([next(it) for _ in acc] if isinstance(acc, list)
                                          else next(it)) for acc in sums]
        if firsts:
            alpha = next(it)
            if next_image is not None:
                sides = (next(it), next(it))
        last = next(it)
        col += 6
    if next_image is not None:
        return sums, alpha, col, sides
    return sums, alpha, col

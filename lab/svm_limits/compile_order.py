"""How a Blender's Cycles orders a shader's SVM program: small graphs whose
peak stack tells pass order from on-demand order. Run in the Blender to
measure, with Cycles' summary in the log:

    blender -b --factory-startup --debug-cycles --verbose 4 [--log-level trace] \\
        -P lab/svm_limits/compile_order.py -- CASE [K]

(`--log-level trace` from 5.0 on), then read "Peak stack usage" under
"Shader name: M". CASE:
- values_first: K values (x + i, then sine) made first, summed after;
- one_sum: K texture reads, each scaled and summed into one sum;
- two_sums: the same reads summed into two sums, one to the emission's
  colour, one to its strength.
K defaults to 30 for values_first, 20 for the sums.
"""
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
case = args[0]
K = int(args[1]) if len(args) > 1 else (30 if case == "values_first" else 20)

mat = bpy.data.materials.new("M")
mat.use_nodes = True
nt = mat.node_tree
for n in list(nt.nodes):
    if n.type != "OUTPUT_MATERIAL":
        nt.nodes.remove(n)
out = next(n for n in nt.nodes if n.type == "OUTPUT_MATERIAL")
tc = nt.nodes.new("ShaderNodeTexCoord")
em = nt.nodes.new("ShaderNodeEmission")


def node(kind, op=None):
    n = nt.nodes.new(kind)
    if op:
        n.operation = op
    return n


def vmath(op, a, b):
    n = node("ShaderNodeVectorMath", op)
    nt.links.new(a, n.inputs[0])
    nt.links.new(b, n.inputs[1])
    return n.outputs[0]


if case == "values_first":
    sep = node("ShaderNodeSeparateXYZ")
    nt.links.new(tc.outputs["UV"], sep.inputs[0])
    values = []
    for i in range(K):
        a = node("ShaderNodeMath", "ADD")
        a.inputs[1].default_value = float(i)
        nt.links.new(sep.outputs[0], a.inputs[0])
        s = node("ShaderNodeMath", "SINE")
        nt.links.new(a.outputs[0], s.inputs[0])
        values.append(s.outputs[0])
    acc = values[0]
    for v in values[1:]:
        a = node("ShaderNodeMath", "ADD")
        nt.links.new(acc, a.inputs[0])
        nt.links.new(v, a.inputs[1])
        acc = a.outputs[0]
    nt.links.new(acc, em.inputs["Strength"])
else:
    img = bpy.data.images.new("I", 8, 8, alpha=True)
    A = B = None
    for i in range(K):
        t = node("ShaderNodeTexImage")
        t.image = img
        off = node("ShaderNodeVectorMath", "ADD")
        off.inputs[1].default_value = (i * 0.1, 0.0, 0.0)
        nt.links.new(tc.outputs["UV"], off.inputs[0])
        nt.links.new(off.outputs[0], t.inputs[0])
        fa = vmath("MULTIPLY", t.outputs["Color"], tc.outputs["Normal"])
        fb = vmath("MULTIPLY", t.outputs["Color"], tc.outputs["Object"])
        A = fa if A is None else vmath("ADD", A, fa)
        B = fb if B is None else vmath("ADD", B, fb)
    nt.links.new(A, em.inputs["Color"])
    if case == "two_sums":
        sep = node("ShaderNodeSeparateXYZ")
        nt.links.new(B, sep.inputs[0])
        nt.links.new(sep.outputs[0], em.inputs["Strength"])
nt.links.new(em.outputs[0], out.inputs["Surface"])
bpy.data.objects["Cube"].active_material = mat
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.samples = 1
scene.render.resolution_x = scene.render.resolution_y = 32
scene.render.filepath = "/tmp/compile_order.png"
bpy.ops.render.render(write_still=True)

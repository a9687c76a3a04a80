"""The part of the clothbake add-on that knows nothing of Blender.

Pure Python (standard library only), so it runs and is tested with plain
pytest outside Blender: reading lookup manifests, the direction maths of the
lookup, the per-quad texel layout and local frames, clothbake scene JSON and
OBJ meshes. The Blender layer (`clothbake.blender`) turns these into
objects, attributes and nodes.
"""

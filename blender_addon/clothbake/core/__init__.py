"""The part of the clothbake add-on that knows nothing of Blender.

Python with the standard library and numpy (Debian's python3-numpy, which
Blender's Python imports too; OpenImageIO where the material's images are
read), so it runs and is tested with plain pytest outside Blender: reading
lookup and material manifests, the direction maths, the per-quad texel
layout and local frames, clothbake scene JSON and OBJ meshes, the material
re-packed for nodes, the material bake's settings table and running the
clothbake program. The Blender layer (`clothbake.blender`) turns these into
objects, attributes, nodes and operators.
"""

"""The Blender layer of the add-on: properties, operators, panels, the node
builder and the scene import/export. Everything that needs `bpy` lives here;
the maths it relies on lives in `clothbake.core`."""

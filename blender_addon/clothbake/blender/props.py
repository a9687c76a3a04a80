"""The settings an artist edits: per object (`obj.clothbake`, props_cloth.py:
the cloth and how it sits on the mesh) and per scene (`scene.clothbake`,
props_scene.py: files, bake, comparison, the reference renderer's and the
material's settings). Properties only: what runs the program or writes a
file is an operator's."""
import bpy

from .props_cloth import ClothbakeObjectSettings, ClothbakeWifColor
from .props_scene import ClothbakeSceneSettings

CLASSES = (ClothbakeWifColor, ClothbakeObjectSettings, ClothbakeSceneSettings)


def register_extra():
    bpy.types.Object.clothbake = bpy.props.PointerProperty(type=ClothbakeObjectSettings)
    bpy.types.Scene.clothbake = bpy.props.PointerProperty(type=ClothbakeSceneSettings)


def unregister_extra():
    del bpy.types.Scene.clothbake
    del bpy.types.Object.clothbake

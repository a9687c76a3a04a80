"""Times every Cycles render of a Blender session, for scripts that render
through bpy.ops.render.render() and are not ours to change (the add-on's
headless route). Run it with -P before the script that renders:

  CLOTHBAKE_RENDER_CLOCK=OUT.json blender -b --factory-startup \
      --python-exit-code 1 -P render_clock.py -P other_script.py -- ...

Registers render_init / render_complete handlers (render_cancel too) and
writes OUT.json after every render: a list of {wall_seconds, cpu_seconds}
(wall: time.perf_counter; cpu: user + system seconds of the Blender process
from getrusage, all its threads), plus the process's seconds from this
script's start to the first render (start-up of the rest: add-on, scene
import, lookup images).
"""
import json
import os
import resource
import time

import bpy

_OUT = os.environ.get("CLOTHBAKE_RENDER_CLOCK")
_T0 = time.perf_counter()
_state = {"renders": [], "before_first_render_seconds": None, "_start": None}


def _cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


@bpy.app.handlers.persistent
def _init(*_):
    now = time.perf_counter()
    if _state["before_first_render_seconds"] is None:
        _state["before_first_render_seconds"] = now - _T0
    _state["_start"] = (now, _cpu())


@bpy.app.handlers.persistent
def _done(*_):
    if _state["_start"] is None:
        return
    t, c = _state["_start"]
    _state["renders"].append({"wall_seconds": time.perf_counter() - t, "cpu_seconds": _cpu() - c})
    _state["_start"] = None
    if _OUT:
        with open(_OUT + ".tmp", "w") as f:
            json.dump({k: v for k, v in _state.items() if not k.startswith("_")}, f, indent=2)
        os.replace(_OUT + ".tmp", _OUT)


bpy.app.handlers.render_init.append(_init)
bpy.app.handlers.render_complete.append(_done)
bpy.app.handlers.render_cancel.append(_done)

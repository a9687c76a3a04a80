"""The window driver: a test in Blender's real window (under Xvfb) runs
its steps from a timer so that the window draws between them.

A step is a function run once; ("wait", predicate, limit) is polled every
0.5 s until it holds (a failed check after `limit` seconds, and the run
ends); ("shot", *args) calls shot(*args) 1.5 s after the step before it,
once the window has redrawn. Each step is announced ("step i/n name at
t s": where a hung run stopped). After the last step, or at a step's
exception (its traceback printed, counted as a failure), the result goes
to `result_path` ("passed", or the failed checks one a line) and Blender
quits: quit_blender exits 0 whatever happened, the shell script reads it."""
import os
import time
import traceback

from lib.checks import check, failures, summary


def area(kind, window=0):
    """(window, its first area of `kind`, that area's main region); area and
    region None when the window has no such area."""
    import bpy
    win = bpy.context.window_manager.windows[window]
    found = next((a for a in win.screen.areas if a.type == kind), None)
    return win, found, region(found) if found is not None else None


def region(found, kind="WINDOW"):
    return next(r for r in found.regions if r.type == kind)


def _name(step):
    if isinstance(step, tuple):
        return step[1] if step[0] == "shot" else step[1].__name__
    return step.__name__


def drive(steps, result_path, shot=None, first_interval=2.0):
    """Registers the timer that runs `steps` (see the module's docstring)."""
    import bpy
    state = {"i": 0, "since": time.time()}
    start = time.time()

    def stop():
        state["i"] = len(steps)

    def tick():
        try:
            if state["i"] >= len(steps):
                summary()
                with open(result_path, "w") as f:
                    f.write("\n".join(failures) if failures else "passed")
                bpy.ops.wm.quit_blender()
                return None
            step = steps[state["i"]]
            if state.get("announced") != state["i"]:
                state["announced"] = state["i"]
                print(f"step {state['i'] + 1}/{len(steps)} {_name(step)} at "
                      f"{time.time() - start:.0f} s", flush=True)
            if isinstance(step, tuple) and step[0] == "shot":
                if time.time() - state["since"] < 1.5:
                    return 0.5
                shot(*step[1:])
            elif isinstance(step, tuple):
                _, done, limit = step
                if not done():
                    if time.time() - state["since"] > limit:
                        check(False, f"{done.__name__} within {limit} s")
                        stop()
                    return 0.5
            else:
                step()
            state["i"] += 1
            state["since"] = time.time()
            return 0.5
        except Exception:
            traceback.print_exc()
            failures.append("exception")
            stop()
            return 0.5

    os.makedirs(os.path.dirname(result_path), exist_ok=True)
    bpy.app.timers.register(tick, first_interval=first_interval)


def cleared(setting):
    """A wait step's predicate: the scene's clothbake.<setting> (a modal
    operator's running flag, as the panel shows it) is off."""
    import bpy

    def done():
        return not getattr(bpy.context.scene.clothbake, setting)
    done.__name__ = f"{setting} off"
    return done


def screenshot(path, win=None, area=None, checked=True):
    """What the X display shows, as a PNG at `path`: the whole screen, or
    `area` of the window `win`. Taken from the X server (xwd, netpbm's
    xwdtopnm, OpenImageIO) rather than by Blender's screenshot operators,
    which read the window's front buffer: under Xvfb that reads black on
    4.3 and 5.2 while the window draws. With `checked`, a shot with no
    contrast at all is a failed check (a window that drew nothing). Returns
    the path."""
    import subprocess

    import numpy as np
    import OpenImageIO as oiio
    xwd = subprocess.run(["xwd", "-root", "-silent"], capture_output=True, check=True).stdout
    pnm = subprocess.run(["xwdtopnm"], input=xwd, capture_output=True, check=True).stdout
    raw = path + ".pnm"
    with open(raw, "wb") as f:
        f.write(pnm)
    image = oiio.ImageBuf(raw)
    if area is not None:
        # Blender's area rectangles count from the window's bottom-left
        # corner; the X screen's rows from its top. The window is placed at
        # the screen's origin by Xvfb.
        top = win.height - (area.y + area.height)
        roi = oiio.ROI(area.x, area.x + area.width, top, top + area.height)
        image = oiio.ImageBufAlgo.cut(image, roi)
    image.write(path)
    os.remove(raw)
    spread = float(np.asarray(image.get_pixels(oiio.FLOAT))[..., :3].std())
    if checked:
        check(spread > 0.01, f"screenshot {os.path.basename(path)} shows the window (spread {spread:.3f})")
    return path

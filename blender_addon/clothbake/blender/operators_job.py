"""What the add-on's operators share: finding the program, reporting a
refusal, and ProgramJob, the modal operator that runs a bake (lookup or
material) through core/program.py's Job.

Every refused input is a ClothbakeError, reported as an ERROR with the
program's or the reader's message ("file: field: message") and the
operator cancelled: never a traceback.
"""
import textwrap

import bpy

from ..core import program as runner
from ..core.errors import ClothbakeError
from . import prefs

# A bake estimated to take longer than this asks before it starts.
CONFIRM_SECONDS = 60.0
# The confirmation's width in pixels, and the characters of a line that fit it
# (a label is cut with an ellipsis where it overflows).
DIALOG_WIDTH, DIALOG_CHARS = 480, 72


def program_path(context):
    program = prefs.program_path(context)
    if program is None:
        raise ClothbakeError("the clothbake program was not found; set its path in the add-on's "
                             "preferences (Edit > Preferences > Add-ons > clothbake)")
    return program


def redraw(context, kinds=None):
    """Tags every area for redraw, or only the areas of `kinds` (a set of
    area types)."""
    wm = context.window_manager
    for window in wm.windows:
        for area in window.screen.areas:
            if kinds is None or area.type in kinds:
                area.tag_redraw()


class Refused(ClothbakeError):
    """Several objects refused at once: one report each."""

    def __init__(self, errors):
        super().__init__("; ".join(str(e) for e in errors))
        self.errors = errors


def report_error(op, e):
    for err in getattr(e, "errors", [e]):
        op.report({"ERROR"}, str(err))


class ProgramJob:
    """The program run in the background for an operator (Bake, Bake
    material): modal, progress from its stderr lines ("bake NN%", "material
    NN%"), Esc kills it and removes what it left half-written; an estimate
    first, and a confirmation dialog when it is over CONFIRM_SECONDS.
    Synchronous in background mode and scripts. One job at a time, whichever
    kind (the machine's cores are the job's).

    A subclass states `_kind` (the settings' prefix: bake_running,
    bake_progress, bake_status; material_...), `_verb`, `_thing`, `_job`
    and `_advice` (the confirmation's words), `_estimator` (a function
    context -> (seconds, bytes)), and implements _command(context) -> (argv,
    output folder) and _succeeded(scene, folder) -> operator result."""
    _running = False  # one job at a time: set on ProgramJob itself
    _kind = "bake"
    _verb = "baking"
    _thing = "lookup"
    _job = "bake"
    _advice = ()
    _estimator = None

    def _estimate(self, context):
        return self._estimator(context)[0]

    def _dialog_lines(self, context):
        """The confirmation's lines: the estimate, its notes (what the bake
        chose and why) each wrapped to the dialog's width, the advice."""
        estimate = getattr(context.scene.clothbake, f"{self._kind}_estimate")
        text, *notes = estimate.split("; ")
        lines = [f"This {self._job} takes {text}."]
        for note in notes:
            lines += textwrap.wrap(note[:1].upper() + note[1:] + ".", DIALOG_CHARS)
        return [*lines, *self._advice]

    def _set(self, scene, name, value):
        setattr(scene.clothbake, f"{self._kind}_{name}", value)

    def _start_report(self, scene, out_dir):
        self._set(scene, "running", True)
        self._set(scene, "progress", 0.0)
        self._set(scene, "status", f"{self._verb} into {out_dir}")

    def _finish(self, scene, code, stderr_lines, out_dir):
        self._set(scene, "running", False)
        if code == 0:
            self._set(scene, "progress", 1.0)
            try:
                return self._succeeded(scene, out_dir)
            except ClothbakeError as e:  # baked, but not applied
                self._set(scene, "status", f"baked into {out_dir}, not applied: {e}")
                report_error(self, e)
                return {"CANCELLED"}
        message = runner.program_error(stderr_lines, self._kind, code)
        self._set(scene, "status", "failed: " + message)
        self.report({"ERROR"}, message)
        return {"CANCELLED"}

    def _refuse(self, message):
        self.report({"ERROR"}, message)
        return {"CANCELLED"}

    def execute(self, context):
        """Background mode and scripts: the program runs to its end here. In
        the UI (after invoke, or its confirmation), it starts in the
        background (modal)."""
        if ProgramJob._running:
            return self._refuse("a bake is running already")
        if not bpy.app.background and context.window is not None:
            return self._start_modal(context)
        try:
            args, out_dir = self._command(context)
        except ClothbakeError as e:
            return self._refuse(str(e))
        self._start_report(context.scene, out_dir)
        try:
            code, lines = runner.run_job(args)
        except ClothbakeError as e:
            self._set(context.scene, "running", False)
            return self._refuse(str(e))
        return self._finish(context.scene, code, lines, out_dir)

    def invoke(self, context, event):
        if bpy.app.background:
            return self.execute(context)
        if ProgramJob._running:
            return self._refuse("a bake is running already")
        # The estimate first (a second or two): a long bake asks before it
        # starts, with its seconds and bytes (a first full bake can run past
        # 10 minutes, and should not do so with no word beforehand).
        try:
            seconds = self._estimate(context)
        except ClothbakeError as e:
            return self._refuse(str(e))
        if seconds > CONFIRM_SECONDS:
            return context.window_manager.invoke_props_dialog(self, width=DIALOG_WIDTH)
        return self._start_modal(context)

    def draw(self, context):
        col = self.layout.column()
        for i, line in enumerate(self._dialog_lines(context)):
            col.label(text=line, icon="TIME" if i == 0 else "NONE")

    def _start_modal(self, context):
        try:
            args, out_dir = self._command(context)
            self._job = runner.Job(args, out_dir)
        except ClothbakeError as e:
            return self._refuse(str(e))
        ProgramJob._running = True
        self._scene = context.scene  # the baked scene, whichever is shown later
        self._start_report(self._scene, out_dir)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set(f"clothbake: {self._verb} 0% (Esc to cancel)")
        return {"RUNNING_MODAL"}

    def _show_progress(self, context):
        """The progress in the panel, the cursor and the status bar, when its
        percent moved. Only then: a scene property set re-evaluates the
        scene and redraws the viewports, and redrawing every area five
        times a second took a core from the bake under Xvfb's software GL."""
        percent = int(round(self._job.progress * 100))
        if percent == getattr(self, "_shown_percent", None):
            return
        self._shown_percent = percent
        self._set(self._scene, "progress", self._job.progress)
        context.window_manager.progress_update(percent)
        context.workspace.status_text_set(f"clothbake: {self._verb} {percent}% (Esc to cancel)")
        redraw(context, {"PROPERTIES"})

    def _end_modal(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        ProgramJob._running = False
        redraw(context)

    def _cancel(self, context):
        """Esc: the program killed, what it left half-written removed."""
        self._job.cancel()
        self._end_modal(context)
        self._set(self._scene, "running", False)
        self._set(self._scene, "status", f"cancelled; the previous {self._thing} (if any) is "
                  "unchanged")
        self.report({"WARNING"}, f"clothbake {self._kind} cancelled")
        return {"CANCELLED"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            return self._cancel(context)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        code = self._job.poll()
        self._show_progress(context)
        if code is None:
            return {"RUNNING_MODAL"}
        self._end_modal(context)
        return self._finish(self._scene, code, self._job.lines, self._job.out_dir)


class EstimateJob:
    """An Estimate button: `_estimator(context)` runs the program's
    --estimate for the job these settings would start; the summary it
    stores in scene.clothbake.<_kind>_estimate is reported."""
    _kind = "bake"
    _estimator = None

    def execute(self, context):
        try:
            self._estimator(context)
        except ClothbakeError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        summary = getattr(context.scene.clothbake, f"{self._kind}_estimate")
        self.report({"INFO"}, f"clothbake {self._kind}: {summary}")
        return {"FINISHED"}

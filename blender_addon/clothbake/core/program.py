"""Running the clothbake program, with no Blender in sight: a command run to
its end (estimates, the reference render, compare), and a long job (a bake,
a material bake) run in the background with its progress read from stderr,
cancellable, and cleaned up after when killed.

The program's side of the conversation: with CLOTHBAKE_PROGRESS=lines it
prints "bake NN%" / "material NN%" lines on stderr; a refused input ends
with one "clothbake: error: FILE: FIELD: message" line and a non-zero exit;
a folder output is written as NAME.tmp-PID and swapped in, the folder it
replaces set aside as NAME.old-PID meanwhile (core/defaults.py).
"""
import os
import queue
import re
import shutil
import subprocess
import threading

from .defaults import folder_siblings
from .errors import ClothbakeError

PROGRESS = re.compile(r"^(?:bake|render|material)\s+(\d+)%")
ERROR_PREFIX = "clothbake: error: "
# A cancelled job gets this long to end on SIGTERM before SIGKILL.
KILL_WAIT_SECONDS = 10


def program_error(stderr_lines, command, code):
    """The program's own error message, else its last lines."""
    for line in reversed(stderr_lines):
        if line.startswith(ERROR_PREFIX):
            return line[len(ERROR_PREFIX):].strip()
    tail = " | ".join(l.strip() for l in stderr_lines[-3:] if l.strip())
    return f"clothbake {command} failed (exit status {code})" + (f": {tail}" if tail else "")


def run(args, command):
    """Runs the program to its end; returns stdout. Raises ClothbakeError
    with the program's message when it fails."""
    try:
        done = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                              stdin=subprocess.DEVNULL)
    except OSError as e:
        raise ClothbakeError(f"cannot run the clothbake program: {e.strerror}", args[0]) from None
    if done.returncode != 0:
        raise ClothbakeError(program_error(done.stderr.splitlines(), command, done.returncode))
    return done.stdout


def _progress_environment():
    return dict(os.environ, CLOTHBAKE_PROGRESS="lines")


def run_job(args):
    """A job run to its end here (background mode, scripts): (exit status,
    stderr lines). Raises ClothbakeError when the program cannot start."""
    try:
        done = subprocess.run(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              stdin=subprocess.DEVNULL, text=True, env=_progress_environment())
    except OSError as e:
        raise ClothbakeError(f"cannot run the clothbake program: {e.strerror}", args[0]) from None
    return done.returncode, done.stderr.splitlines()


def clean_after_kill(out_dir, pid):
    """What a killed job may leave (docs/formats/lookup.md "Folder layout"):
    its temporary folder, or an old folder half swapped out."""
    temp, old = folder_siblings(out_dir, pid)
    shutil.rmtree(temp, ignore_errors=True)
    if os.path.isdir(old):
        if os.path.isdir(out_dir):
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(old, out_dir)


def kill_job(proc, out_dir):
    """Ends a running job (lookup or material bake) and removes what it left:
    SIGTERM (its output is only ever written atomically), SIGKILL after
    KILL_WAIT_SECONDS."""
    proc.terminate()
    try:
        proc.wait(timeout=KILL_WAIT_SECONDS)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    clean_after_kill(out_dir, proc.pid)


def _read_lines(stream, out):
    """On a thread: every line of `stream` into `out`, then None."""
    for line in stream:
        out.put(line.rstrip("\n"))
    out.put(None)


class Job:
    """The program writing `out_dir` in the background. Its stderr is read
    on a thread (a full pipe would stall it); poll() takes what was read
    and says when it has ended. Raises ClothbakeError when it cannot start."""

    def __init__(self, args, out_dir):
        self.out_dir = out_dir
        try:
            self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                         stdin=subprocess.DEVNULL, text=True,
                                         env=_progress_environment())
        except OSError as e:
            raise ClothbakeError(f"cannot run the clothbake program: {e.strerror}") from None
        self.lines = []          # stderr so far
        self.progress = 0.0      # the last progress line's fraction
        self._queue = queue.Queue()
        self._read_all = False
        threading.Thread(target=_read_lines, args=(self.proc.stderr, self._queue),
                         daemon=True).start()

    def _drain(self):
        while True:
            try:
                line = self._queue.get_nowait()
            except queue.Empty:
                return
            if line is None:
                self._read_all = True
                continue
            self.lines.append(line)
            m = PROGRESS.match(line)
            if m:
                self.progress = int(m.group(1)) / 100.0

    def poll(self):
        """Takes the lines read since the last call; returns the exit status
        once the program has ended and all its stderr is read, else None."""
        self._drain()
        code = self.proc.poll()
        return code if code is not None and self._read_all else None

    def cancel(self):
        """Kills the program and removes what it left half-written."""
        kill_job(self.proc, self.out_dir)


def duration_text(seconds):
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def texels_note(report):
    """From a material report or estimate (`clothbake material`), the
    warning the program prints when the texels leave fewer than 2 per
    thread, short for the panel, with the Texels it advises (at least 4 per
    thread); "" when there are enough (or the threads are not known: a VDB
    volume)."""
    per_thread, advised = report.get("texels_per_thread"), report.get("texels_advised")
    if not per_thread or not advised:
        return ""
    return (f"{per_thread:.2g} texels per thread: too few to show the weave "
            f"(Texels {advised} gives {advised * per_thread / report['texels']:.2g})")


def plan_note(report):
    """From a material report or estimate, what the bake chose and why, short
    for the panel: "per crossing at 8 texels (30 blocks): the whole repeat
    spans 62 threads: ..." (the program's `plan` less the bytes it holds); "" for
    settings the user fixed, or a report without a plan."""
    plan = report.get("plan", "")
    mode, _, why = plan.partition(": ")
    why = why.split("; the bake holds")[0]
    if not mode or not why or why == "as asked":
        return ""
    return f"{mode}: {why}"


def estimate_text(seconds, size, bound="", what="", disk=None):
    """An estimate as the panel shows it (short: the panel is narrow); `bound`
    ("up to ") when the size is an upper bound; `what` names the size
    ("peak memory"); `disk`, bytes, the folder's size on disk (MB, as a file
    manager shows it)."""
    mib = max(1, round(size / 2**20))
    text = f"about {duration_text(seconds)}, {bound}{mib} MiB" + (f" {what}" if what else "")
    if disk is not None:
        text += f", about {max(1, round(disk / 1e6))} MB on disk"
    return text

"""Running the clothbake program under test (the first argument after
Blender's "--")."""
import os
import subprocess
import sys


def run(args):
    """Runs `clothbake ARGS`; returns its stdout. A non-zero exit raises
    RuntimeError with the command and the end of its stderr."""
    exe = os.path.abspath(sys.argv[sys.argv.index("--") + 1])
    p = subprocess.run([exe] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                       text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(args) + ": " + p.stderr[-800:])
    return p.stdout

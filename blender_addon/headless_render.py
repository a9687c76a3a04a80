"""Entry point of the headless route (Blender runs this file with -P):
enables the clothbake add-on from this folder, then hands the arguments
after "--" to clothbake.blender.headless.main. See that module."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import addon_utils  # noqa: E402

addon_utils.enable("clothbake", default_set=True, handle_error=None)
from clothbake.blender import headless  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
code = headless.main(argv)
if code:
    sys.exit(code)

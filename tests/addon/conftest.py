"""pytest set-up for the add-on's bpy-free core: puts blender_addon/ on the
path, and gives tests the clothbake binary (CLOTHBAKE_BIN) when ctest runs
them."""
import os
import sys

import pytest

SOURCE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "blender_addon"))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def clothbake_bin():
    path = os.environ.get("CLOTHBAKE_BIN", os.path.join(SOURCE_DIR, "build", "baker", "clothbake"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"clothbake binary not found at {path} (set CLOTHBAKE_BIN)")
    return path

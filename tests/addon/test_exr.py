"""clothbake.core.exr: a whole EXR passes; every truncation is refused
(Blender 3.4 hangs on a truncated atlas, so Apply checks first)."""
import os

import pytest

from clothbake.core.errors import ClothbakeError
from clothbake.core.exr import check_exr

SOURCE = os.path.join(os.path.dirname(__file__), "..", "..")
REFERENCE = os.path.join(SOURCE, "testscenes", "slab", "reference.exr")


def test_whole_files_pass_with_their_size():
    # Their sizes as OpenImageIO reads them.
    for scene, shape in (("slab", (32, 32)), ("paper", (213, 133))):
        assert check_exr(os.path.join(SOURCE, "testscenes", scene, "reference.exr")) == shape


@pytest.mark.parametrize("fraction", [0.0, 0.001, 0.02, 0.1, 0.5, 0.9, 0.999])
def test_truncated_files_are_refused(tmp_path, fraction):
    data = open(REFERENCE, "rb").read()
    cut = tmp_path / "cut.exr"
    cut.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(ClothbakeError, match=r"cut\.exr: the lookup image is (not an OpenEXR "
                                             r"file|damaged or truncated)"):
        check_exr(str(cut))


def test_a_text_file_is_not_an_exr(tmp_path):
    text = tmp_path / "atlas.exr"
    text.write_text("hello")
    with pytest.raises(ClothbakeError, match="atlas.exr: the lookup image is not an OpenEXR file"):
        check_exr(str(text))

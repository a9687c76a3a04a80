"""Running the program (clothbake.core.program) against a stand-in program:
progress lines, the error message, a job polled to its end, a job killed
and what it left cleaned up."""
import os
import sys
import time

import pytest

from clothbake.core import program
from clothbake.core.defaults import folder_siblings
from clothbake.core.errors import ClothbakeError


def _fake(tmp_path, body):
    """A stand-in program: a Python script with `body`."""
    path = tmp_path / "fake.py"
    path.write_text("import sys, time\n" + body)
    return [sys.executable, str(path)]


def test_progress_and_error_lines():
    m = program.PROGRESS.match("material  42% 1.3s")
    assert m is not None and m.group(1) == "42"
    assert program.PROGRESS.match("baked 42%") is None
    assert program.program_error(["bake  10%", "clothbake: error: a.json: b: bad"], "bake",
                                 1) == "a.json: b: bad"
    assert program.program_error(["x", "", "y"], "bake", 3) == \
        "clothbake bake failed (exit status 3): x | y"


def test_run_returns_stdout_or_raises(tmp_path):
    assert program.run(_fake(tmp_path, "print('out')"), "render") == "out\n"
    with pytest.raises(ClothbakeError, match="^a: b: no$"):
        program.run(_fake(tmp_path, "print('clothbake: error: a: b: no', file=sys.stderr);"
                                    "sys.exit(2)"), "render")
    with pytest.raises(ClothbakeError, match="cannot run the clothbake program"):
        program.run([str(tmp_path / "missing")], "render")


def test_job_polled_to_its_end(tmp_path):
    job = program.Job(_fake(tmp_path, "for p in (10, 60):\n"
                                      "    print(f'bake {p}%', file=sys.stderr, flush=True)\n"),
                      str(tmp_path / "out"))
    deadline = time.time() + 30
    code = None
    while code is None and time.time() < deadline:
        time.sleep(0.05)
        code = job.poll()
    assert code == 0 and job.progress == 0.6 and job.lines == ["bake 10%", "bake 60%"]
    code, lines = program.run_job(_fake(tmp_path, "print('material 5%', file=sys.stderr)"))
    assert code == 0 and lines == ["material 5%"]


@pytest.mark.parametrize("existing", [False, True])
def test_a_killed_job_leaves_nothing(tmp_path, existing):
    out = str(tmp_path / "bake")
    if existing:
        os.makedirs(out)
    # The stand-in writes as the program does: NAME.tmp-PID, and the old
    # folder set aside as NAME.old-PID half-way through the swap.
    job = program.Job(_fake(tmp_path, f"""import os
out = {out!r}
tmp, old = out + '.tmp-' + str(os.getpid()), out + '.old-' + str(os.getpid())
os.makedirs(tmp)
if os.path.isdir(out):
    os.rename(out, old)
print('bake 5%', file=sys.stderr, flush=True)
time.sleep(60)
"""), out)
    deadline = time.time() + 30
    while job.progress == 0 and time.time() < deadline:
        time.sleep(0.05)
        job.poll()
    job.cancel()
    temp, old = folder_siblings(out, job.proc.pid)
    assert not os.path.exists(temp) and not os.path.exists(old)
    assert os.path.isdir(out) == existing


def test_estimate_text():
    assert program.estimate_text(42, 3 * 2**20) == "about 42 s, 3 MiB"
    assert program.estimate_text(600, 10, bound="up to ") == "about 10 min, up to 1 MiB"
    assert (program.estimate_text(90, 900 * 2**20, what="peak memory")
            == "about 2 min, 900 MiB peak memory")
    assert (program.estimate_text(300, 5 * 2**30, what="peak memory", disk=120.4e6)
            == "about 5 min, 5120 MiB peak memory, about 120 MB on disk")
    assert program.duration_text(7200) == "2.0 h"


def test_texels_note():
    # The program's figures (cli.material_estimate): wi_32twill's 62 threads.
    assert program.texels_note({"texels": 32, "texels_per_thread": 32 / 62,
                                "texels_advised": 256}) == \
        "0.52 texels per thread: too few to show the weave (Texels 256 gives 4.1)"
    assert program.texels_note({"texels": 32, "texels_per_thread": 16.0}) == ""
    assert program.texels_note({"texels": 32}) == ""   # a VDB volume: threads unknown


def test_plan_note():
    # The program's plans (cli.material_estimate): what was chosen and why,
    # without the bytes; nothing for settings the user fixed.
    auto = {"plan": "per crossing at 8 texels (30 blocks): the whole repeat spans 62 threads: "
                    "0.52 texels a thread at 32, below 2; the bake holds 46 MiB before its "
                    "table grows"}
    assert program.plan_note(auto) == \
        "per crossing at 8 texels (30 blocks): the whole repeat spans 62 threads: 0.52 texels " \
        "a thread at 32, below 2"
    paper = {"plan": "the whole repeat at 32 texels: 16.0 texels a thread, within the budget; "
                     "the bake holds 433 MiB before its table grows"}
    assert program.plan_note(paper) == \
        "the whole repeat at 32 texels: 16.0 texels a thread, within the budget"
    asked = {"plan": "per crossing at 8 texels (30 blocks): as asked; the bake holds 46 MiB "
                     "before its table grows"}
    assert program.plan_note(asked) == ""
    assert program.plan_note({}) == ""

"""A Simulation in a notebook (swarmsim/render/notebook.py): its frame as a PNG, a stretch of
the run as an inline HTML5 video, one error line without IPython, and examples/watch_k.ipynb
executed by nbclient in a kernel of this interpreter."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.render import notebook

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "examples" / "watch_k.ipynb"
RUN = {"world": "tiny", "controller": "ggc", "robots": 30, "groups": 2, "seed": 0,
       "max_ticks": 500}


def _decode_video(mp4: bytes, tmp_path: Path) -> np.ndarray:
    import imageio.v3 as iio

    path = tmp_path / "v.mp4"
    path.write_bytes(mp4)
    return iio.imread(path, index=None)


def test_a_simulation_shows_itself_as_its_current_frame():
    import imageio.v3 as iio

    sim = Simulation(**RUN)
    for _ in range(5):
        sim.advance()
    image = iio.imread(sim._repr_png_(), extension=".png")
    np.testing.assert_array_equal(image, sim.render(width=640))
    assert image.shape[1] == 640 and sim.tick == 5


def test_video_advances_the_run_as_run_would_and_shows_inline(tmp_path):
    sim = Simulation(**RUN)
    sim.advance()
    video = sim.video(ticks=25, every=10, width=160, fps=12)
    plain = Simulation(**RUN)
    for _ in range(26):
        plain.advance()
    assert sim.tick == 26 and (video.first_tick, video.last_tick) == (1, 26)
    np.testing.assert_array_equal(sim.positions, plain.positions)
    np.testing.assert_array_equal(sim.messages, plain.messages)
    # ticks 1, 11, 21 and the last, 26
    assert video.frames == 4
    frames = _decode_video(video.mp4, tmp_path)
    assert frames.shape[0] == 4 and frames.shape[2] == 160
    html = video._repr_html_()
    assert html.startswith("<video") and "data:video/mp4;base64," in html
    import base64

    encoded = html.split("base64,", 1)[1].split('"', 1)[0]
    assert base64.b64decode(encoded) == video.mp4
    assert video.save(tmp_path / "k.mp4").read_bytes() == video.mp4


def test_video_stops_with_the_run():
    sim = Simulation(**{**RUN, "max_ticks": 12})
    video = sim.video(every=5, width=160)
    assert sim.stop_reason is not None and video.last_tick == sim.tick == 12
    assert video.frames == 4  # ticks 0, 5, 10 and 12


@pytest.mark.parametrize(("key", "value"), [("ticks", -1), ("every", 0), ("every", 2.5)])
def test_video_refuses_bad_counts(key, value):
    sim = Simulation(**RUN)
    with pytest.raises(ConfigError, match=f"key '{key}': must be an integer"):
        sim.video(**{key: value})
    assert sim.tick == 0


def test_show_without_ipython_is_one_line_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "IPython", None)  # import IPython raises ImportError
    sim = Simulation(**RUN)
    with pytest.raises(ConfigError) as caught:
        sim.show()
    message = str(caught.value)
    assert "\n" not in message and "IPython" in message
    assert "pip install 'swarmsim[notebook]'" in message


def test_show_displays_the_frame_through_ipython(monkeypatch):
    pytest.importorskip("IPython")
    from IPython import display

    shown = []
    monkeypatch.setattr(display, "display", lambda *objs: shown.extend(objs))
    sim = Simulation(**RUN)
    sim.show(width=320)
    assert len(shown) == 1 and isinstance(shown[0], display.Image)
    assert shown[0].data == notebook.png_bytes(sim.render(width=320))


def test_importing_swarmsim_and_running_imports_no_ipython():
    code = ("import sys; from swarmsim import Simulation; "
            "s = Simulation('tiny', robots=5, seed=0, max_ticks=3); s.run(); s._repr_png_(); "
            "print('IPython' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300)
    assert out.stdout.strip() == "False"


def test_the_committed_notebook_has_no_outputs():
    cells = json.loads(NOTEBOOK.read_text(encoding="utf-8"))["cells"]
    code = [c for c in cells if c["cell_type"] == "code"]
    assert code and all(not c["outputs"] and c["execution_count"] is None for c in code)


def test_the_example_notebook_executes(tmp_path, monkeypatch):
    for package in ("nbclient", "nbformat", "ipykernel"):
        pytest.importorskip(package, reason=f"{package} is not installed (the extra notebook)")
    import nbformat
    from nbclient import NotebookClient

    # a kernel of this interpreter, named and found only here: nothing under the user's home
    kernels = tmp_path / "jupyter" / "kernels" / "swarmsim-test"
    kernels.mkdir(parents=True)
    (kernels / "kernel.json").write_text(json.dumps({
        "argv": [sys.executable, "-m", "ipykernel_launcher", "-f", "{connection_file}"],
        "display_name": "swarmsim test", "language": "python"}))
    monkeypatch.setenv("JUPYTER_PATH", str(tmp_path / "jupyter"))
    monkeypatch.setenv("JUPYTER_RUNTIME_DIR", str(tmp_path / "runtime"))
    monkeypatch.setenv("IPYTHONDIR", str(tmp_path / "ipython"))
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(nb, kernel_name="swarmsim-test", timeout=600,
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [out for cell in nb.cells if cell.cell_type == "code" for out in cell.outputs]
    assert not [out for out in outputs if out.output_type == "error"]
    pictures = [out for out in outputs if "image/png" in out.get("data", {})]
    videos = [out for out in outputs if "<video" in out.get("data", {}).get("text/html", "")]
    assert len(pictures) == 2 and len(videos) == 1
    printed = "".join(out.get("text", "") for out in outputs if out.output_type == "stream")
    assert "tick 1200," in printed

"""docs/python.md stays true: every ```python block of it runs, in order, in a folder holding
`frames/` (three RGB-D frames from `deepsea scene`) and `camera.yaml`."""

import os
import re

import pytest

from conftest import CAMERA, SRC, cli


def test_python_md_examples(tmp_path, monkeypatch, capsys):
    pytest.importorskip("OpenImageIO")
    text = open(os.path.join(SRC, "docs", "python.md")).read()
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert len(blocks) >= 4
    (tmp_path / "camera.yaml").write_text(
        "camera:\n" + "".join(f"  {k}: {v}\n" for k, v in CAMERA.items()))
    cli("scene", "--out", tmp_path / "frames", "--frames", 3, "--camera", tmp_path / "camera.yaml")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "python_md"}
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/python.md block {i + 1}", "exec"), namespace)
    out = capsys.readouterr().out
    assert "3 {" in out  # the dataset's length and its sample's arrays

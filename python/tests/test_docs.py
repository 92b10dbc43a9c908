"""docs/python.md stays true: every ```python block of it runs, in order, in a folder holding
`frames/` (three RGB-D frames from `deepsea scene`), `camera.yaml` and `robot_camera.yaml` (the
page's ```yaml block of that name: the same camera with a camera stage)."""

import os
import re

import pytest

from conftest import CAMERA, SRC, cli


def test_python_md_examples(tmp_path, monkeypatch, capsys):
    text = open(os.path.join(SRC, "docs", "python.md")).read()
    blocks = re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)
    assert len(blocks) >= 4
    (tmp_path / "camera.yaml").write_text(
        "camera:\n" + "".join(f"  {k}: {v}\n" for k, v in CAMERA.items()))
    robot = [b for b in re.findall(r"^```yaml\n(.*?)^```", text, flags=re.S | re.M)
             if b.startswith("# robot_camera.yaml")]
    assert len(robot) == 1
    for key, value in CAMERA.items():  # the frames' camera
        assert f"\n  {key}: {value}\n" in robot[0], key
    (tmp_path / "robot_camera.yaml").write_text(robot[0])
    cli("scene", "--out", tmp_path / "frames", "--frames", 3, "--camera", tmp_path / "camera.yaml")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    namespace = {"__name__": "python_md"}
    for i, block in enumerate(blocks):
        # A block that begins "# name.py" is that module: written for the blocks after it
        # (and for spawned workers) to import.
        first = block.splitlines()[0]
        if re.fullmatch(r"# \w+\.py", first):
            (tmp_path / first[2:]).write_text(block)
            continue
        exec(compile(block, f"docs/python.md block {i + 1}", "exec"), namespace)
    out = capsys.readouterr().out
    assert "3 {" in out  # the dataset's length and its sample's arrays

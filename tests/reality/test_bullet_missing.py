"""Without PyBullet (the optional extra): a bullet reality says what to install, without a
traceback; nothing else needs it.  These run whether or not PyBullet is installed (it is made
unimportable here)."""

from __future__ import annotations

import sys

import pytest

from adapt.errors import RealityError
from adapt.reality import open_reality
from adapt.seeds import Streams

from .bullet_scene import CAMERA, REALITY, RUN, WORLD, scenario


def test_without_pybullet_the_error_says_what_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pybullet", None)  # import pybullet now raises ImportError
    with pytest.raises(RealityError) as info:
        open_reality(scenario(), streams=Streams(1))
    message = str(info.value)
    assert "pip install 'adapt[bullet]'" in message
    assert message.startswith("<string>:") and "PyBullet" in message


def test_adapt_run_without_pybullet_says_what_to_install_without_a_traceback(
        monkeypatch: pytest.MonkeyPatch, tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    from adapt.cli import main

    monkeypatch.setitem(sys.modules, "pybullet", None)
    path = tmp_path / "foreign.yaml"
    path.write_text(CAMERA + WORLD + REALITY + RUN)
    status = main(["run", str(path), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status != 0
    assert f"{path}:" in err and "pip install 'adapt[bullet]'" in err
    assert "Traceback" not in err

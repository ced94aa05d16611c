"""A corrupt image says so in adapt's own words only (issue 21: ``libpng error:`` lines came
first, raw, on standard error)."""

from __future__ import annotations

from pathlib import Path

import pytest

from adapt.cli import main

ROOT = Path(__file__).resolve().parents[1]
BRICK = ROOT / "adapt" / "data" / "textures" / "brick.png"


@pytest.fixture()
def corrupt(tmp_path: Path) -> Path:
    data = bytearray(BRICK.read_bytes())
    for i in range(200, 260):  # inside the image data: zlib fails ("invalid distance")
        data[i] ^= 0x5A
    path = tmp_path / "bad.png"
    path.write_bytes(bytes(data))
    return path


def _only_adapt(capfd: pytest.CaptureFixture[str]) -> str:
    err = capfd.readouterr().err
    lines = err.splitlines()
    assert lines and all(line.startswith(("adapt: error: ", "    ")) for line in lines), err
    assert "libpng error" in lines[0], err  # libpng's reason, inside adapt's message
    return err


def test_a_corrupt_texture(corrupt: Path, tmp_path: Path, capfd) -> None:
    text = (ROOT / "scenarios" / "room.yaml").read_text().replace("texture: brick",
                                                                  f"texture: {corrupt}")
    scenario = tmp_path / "s.yaml"
    scenario.write_text(text.replace("../rules/", f"{ROOT / 'rules'}/"))
    assert main(["render", str(scenario), "--out", str(tmp_path / "f.png")]) == 1
    assert "texture file" in _only_adapt(capfd)


def test_a_corrupt_image(corrupt: Path, capfd) -> None:
    assert main(["mmd", str(corrupt), str(BRICK)]) == 1
    assert "not an image OpenCV can decode" in _only_adapt(capfd)

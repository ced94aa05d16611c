"""``mmd`` and ``sync`` on generated images.

Images of any small size (1x1 up to 90x90), 1, 3 or 4 channels, 8 or 16 bits,
flat, noisy or striped, written as PNG, JPEG, TIFF or BMP -- or files that are
not images: garbage, truncated PNGs, text with an image's extension.
"""

from __future__ import annotations

import cv2
import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .harness import Pool, examples, run_checked


@st.composite
def image_files(draw: st.DrawFn) -> tuple[str, bytes]:
    kind = draw(st.integers(0, 9))
    if kind == 0:
        return draw(st.sampled_from([".png", ".jpg", ".txt", ""])), draw(st.binary(max_size=300))
    h = draw(st.sampled_from([1, 2, 7, 60, 90]))
    w = draw(st.sampled_from([1, 3, 8, 80, 90]))
    channels = draw(st.sampled_from([None, 1, 3, 4]))
    sixteen = draw(st.booleans())
    shape = (h, w) if channels is None else (h, w, channels)
    top = 65535 if sixteen else 255
    rng = np.random.default_rng(draw(st.integers(0, 2**16)))
    pattern = draw(st.integers(0, 2))
    if pattern == 0:
        image = np.full(shape, draw(st.integers(0, top)))
    elif pattern == 1:
        image = rng.integers(0, top + 1, shape)
    else:
        image = (np.indices(shape[:2]).sum(axis=0) % 7 * (top // 7))
        if channels is not None:
            image = np.repeat(image[..., None], channels, axis=2)
    image = image.astype(np.uint16 if sixteen else np.uint8)
    ext = draw(st.sampled_from([".png", ".tif", ".bmp", ".jpg"]))
    ok, buf = cv2.imencode(ext, image)
    if not ok:
        ext, buf = ".png", cv2.imencode(".png", image)[1]
    data = buf.tobytes()
    if kind == 1:
        data = data[: draw(st.integers(0, len(data)))]
    return ext, data


def _write(folder, name: str, item: tuple[str, bytes]) -> str:
    path = folder / (name + item[0])
    path.write_bytes(item[1])
    return str(path)


def test_mmd_on_generated_images(pool: Pool) -> None:
    @settings(max_examples=examples(40), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(image_files(), image_files() | st.just(("same", b"")), st.booleans(), st.booleans())
    def check(real: tuple[str, bytes], synth: tuple[str, bytes], out: bool, as_json: bool) -> None:
        folder = pool.outputs()
        real_path = _write(folder, "real", real)
        synth_path = real_path if synth[0] == "same" else _write(folder, "synth", synth)
        argv = ["mmd", real_path, synth_path] + (["--out", str(folder / "o")] if out else [])
        run_checked(pool, argv + (["--json"] if as_json else []))

    check()


def test_sync_on_generated_images(pool: Pool) -> None:
    @settings(max_examples=examples(25), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(image_files())
    def check(real: tuple[str, bytes]) -> None:
        folder = pool.outputs()
        run_checked(pool, ["sync", pool.path("scene.yaml"), "--real", _write(folder, "real", real),
                           "--max-iter", "2", "--out", str(folder / "o")])

    check()

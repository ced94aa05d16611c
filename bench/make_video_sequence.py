"""Regenerate the image sequence of ``scenarios/video-sequence.yaml``.

Run ``python bench/make_video_sequence.py``: it plays the synthetic reality
``scenarios/video/synthetic.yaml`` and writes ``scenarios/video/frames/*.jpg``
and ``scenarios/video/truth.csv`` (see :func:`adapt.reality.record.record_sequence`),
then prints the number of frames and their size.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from adapt.reality.record import record_sequence  # noqa: E402
from adapt.scenario import load_scenario  # noqa: E402

SOURCE = ROOT / "scenarios" / "video" / "synthetic.yaml"
#: JPEG quality of the shipped frames (keeps the sequence well under 2 MB).
QUALITY = 85


def main() -> int:
    out = SOURCE.parent
    for old in (out / "frames").glob("frame_*.jpg"):
        old.unlink()
    rec = record_sequence(load_scenario(SOURCE), out, quality=QUALITY)
    print(f"{rec.frames} frames in {rec.frames_dir.relative_to(ROOT)}, truth in "
          f"{rec.truth.relative_to(ROOT)}; {rec.bytes / 1e6:.2f} MB in all")
    return 0


if __name__ == "__main__":
    sys.exit(main())

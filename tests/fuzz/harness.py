"""Driving ``adapt`` in-process with bad input, and the contract every run must keep.

The contract (``docs/cli.md``):

* the exit status is one of those documented for the subcommand
  (:data:`adapt.cli.exits.COMMAND_STATUSES`);
* status 1 or 2 comes with an ``adapt: error: ...`` line on standard error;
* never a Python traceback, never ``adapt: internal error`` (status 70);
* no input is changed: every file of the workspace's pool keeps its bytes.

The workspace holds a pool of inputs, good and bad: small rule files, a small
scenario (80x60 camera, three frames), images, traces.  Outputs go to a fresh
folder per example, inside the workspace, which is also the current directory
(so default output paths, such as ``runs/<name>``, land there too).
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import os
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from adapt.cli import main
from adapt.cli.exits import COMMAND_STATUSES, Exit

ROOT = Path(__file__).resolve().parents[2]

#: Examples per fuzz test; ``ADAPT_FUZZ_EXAMPLES=500 python -m pytest tests/fuzz`` digs deeper.
EXAMPLES = int(os.environ.get("ADAPT_FUZZ_EXAMPLES", "0")) or None

HALTING_RULES = """\
sp {propose*count (state <s> ^superstate nil -^count 3) --> (<s> ^operator <o> +) (<o> ^name count)}
sp {apply*count*first (state <s> ^operator.name count -^count) --> (<s> ^count 1)}
sp {apply*count (state <s> ^operator.name count ^count <c> < 3) --> (<s> ^count <c> - (+ <c> 1))
   (write |count | (+ <c> 1) (crlf))}
sp {done (state <s> ^count 3) --> (halt)}
"""


def examples(default: int) -> int:
    """The number of examples for a test: ``default``, or ``ADAPT_FUZZ_EXAMPLES``."""
    return EXAMPLES or default


def small_scenario(rules: str = "perception.soar") -> dict[str, Any]:
    """The fuzzed scenario: the room at 80x60 pixels, three frames of reality."""
    room = yaml.safe_load((ROOT / "scenarios" / "room.yaml").read_text(encoding="utf-8"))
    cam = room["camera"]
    scale = 8
    cam.update(fx=cam["fx"] / scale, fy=cam["fy"] / scale, cx=(cam["cx"] + 0.5) / scale - 0.5,
               cy=(cam["cy"] + 0.5) / scale - 0.5, width=640 // scale, height=480 // scale)
    room["reality"] = {"camera_offset_deg": [0.5, -0.3, 0.2], "appearance": {"noise": 1.0}}
    room["goals"] = [{"name": "watch"}]
    room["rules"] = [rules]
    room["run"] = {"fps": 10, "duration": 0.3}
    return room


@dataclass
class Outcome:
    """What one command did."""

    argv: list[str]
    status: int
    out: str
    err: str


def drive(argv: list[str]) -> Outcome:
    """Run ``adapt ARGV`` in this process, capturing its output and status."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as exc:  # argparse: --help, --version, usage errors
            code = exc.code
            status = code if isinstance(code, int) else (0 if code is None else 1)
    return Outcome(argv, int(status), out.getvalue(), err.getvalue())


def command_of(argv: list[str]) -> str:
    """``"trace show"`` for ``["trace", "show", ...]``; ``"rules run"``; ``"render"``."""
    words = [a for a in argv[:2] if not a.startswith("-")]
    if not words:
        return ""
    if words[0] in ("rules", "trace", "schemas", "plugins") and len(words) > 1:
        return f"{words[0]} {words[1]}"
    return words[0]


def check_contract(outcome: Outcome) -> None:
    """Assert the contract of the module docstring (not the inputs: see :class:`Pool`)."""
    text = outcome.out + outcome.err
    context = f"\nargv: {outcome.argv!r}\nstatus: {outcome.status}\nstderr:\n{outcome.err[-3000:]}"
    assert "Traceback (most recent call last)" not in text, context
    assert "internal error" not in outcome.err and outcome.status != Exit.INTERNAL, context
    command = command_of(outcome.argv)
    allowed = COMMAND_STATUSES.get(command, (Exit.OK, Exit.ERROR, Exit.USAGE))
    assert outcome.status in {int(s) for s in allowed}, context
    if outcome.status in (Exit.ERROR, Exit.USAGE):
        differ = command == "trace diff" and "--exit-code" in outcome.argv and "diverge" in outcome.out
        if not differ:
            assert any(line.startswith("adapt: error: ") for line in outcome.err.splitlines()), context


class Pool:
    """The workspace: input files (hashed, to prove no command changes them) and outputs."""

    def __init__(self, root: Path) -> None:
        self.root = root
        self.inputs = root / "inputs"
        self.inputs.mkdir()
        self.files: dict[str, Path] = {}
        self._build()
        self.hashes = self._hash()
        self.originals = {p: p.read_bytes() for p in self.hashes}
        self._count = 0

    # -- building ------------------------------------------------------------------------
    def _add(self, name: str, data: bytes | str) -> Path:
        path = self.inputs / name
        path.write_bytes(data.encode("utf-8") if isinstance(data, str) else data)
        self.files[name] = path
        return path

    def _build(self) -> None:
        import cv2

        self._add("count.soar", HALTING_RULES)
        shutil.copy(ROOT / "rules" / "examples" / "water-jug.soar", self.inputs / "wj.soar")
        self.files["wj.soar"] = self.inputs / "wj.soar"
        shutil.copy(ROOT / "rules" / "mirror" / "perception.soar", self.inputs / "perception.soar")
        self.files["perception.soar"] = self.inputs / "perception.soar"
        self._add("broken.soar", "sp {broken (state <s> ^a 1)\n")
        self._add("empty.txt", "")
        self._add("garbage.bin", bytes(range(256)) * 4)
        self._add("scene.yaml", yaml.safe_dump(small_scenario(), sort_keys=False))
        scene = small_scenario()
        scene.pop("reality"), scene.pop("goals"), scene.pop("rules"), scene.pop("run")
        self._add("plain.yaml", yaml.safe_dump(scene, sort_keys=False))
        rng = np.random.default_rng(3)
        for name, image in {
            "real.png": rng.integers(0, 255, (60, 80, 3), dtype=np.uint8),
            "synth.png": rng.integers(0, 255, (60, 80, 3), dtype=np.uint8),
            "grey16.png": rng.integers(0, 65535, (60, 80), dtype=np.uint16),
            "tiny.png": np.zeros((1, 1, 3), np.uint8),
            "other-size.png": np.zeros((30, 41, 3), np.uint8),
        }.items():
            self._add(name, cv2.imencode(".png", image)[1].tobytes())
        self._add("truncated.png", self.files["real.png"].read_bytes()[:100])
        # a scenario whose floor texture is where a run into inputs/ would draw its floor plan,
        # and whose rules source another file (issue 21: inputs a run reads indirectly)
        (self.inputs / "figures").mkdir()
        self.files["figures/floor.png"] = self.inputs / "figures" / "floor.png"
        self.files["figures/floor.png"].write_bytes(self.files["real.png"].read_bytes())
        self._add("sources.soar", "source perception.soar\n")
        textured = small_scenario(rules="sources.soar")
        textured["world"]["floor"]["texture"] = "figures/floor.png"
        self._add("textured.yaml", yaml.safe_dump(textured, sort_keys=False))
        (self.inputs / "folder").mkdir()
        self.files["folder"] = self.inputs / "folder"
        for level in (5, 3, 1):
            name = f"wj{level}.jsonl"
            status = main(["rules", "run", str(self.files["wj.soar"]), "--trace",
                           str(self.inputs / name), "--trace-level", str(level), "--json"])
            assert status == 0
            self.files[name] = self.inputs / name

    def _hash(self) -> dict[Path, str]:
        return {p: hashlib.sha256(p.read_bytes()).hexdigest()
                for p in sorted(self.inputs.rglob("*")) if p.is_file()}

    # -- using -----------------------------------------------------------------------------
    def outputs(self) -> Path:
        """A fresh, empty folder for one example's outputs."""
        self._count += 1
        return Path(tempfile.mkdtemp(prefix=f"ex{self._count}-", dir=self.root))

    def path(self, name: str) -> str:
        return str(self.files[name])

    def check_inputs_kept(self, outcome: Outcome) -> None:
        """No input was changed or removed (new files beside them are outputs, and allowed)."""
        changed = []
        for path, digest in self.hashes.items():
            try:
                now = hashlib.sha256(path.read_bytes()).hexdigest()
            except OSError:
                now = "(gone)"
            if now != digest:
                changed.append(str(path))
                path.parent.mkdir(parents=True, exist_ok=True)
                path.unlink(missing_ok=True)
                path.write_bytes(self.originals[path])  # so that the next example starts clean
        assert not changed, f"inputs changed by {outcome.argv!r}: {changed}"


def run_checked(pool: Pool, argv: list[str]) -> Outcome:
    """:func:`drive`, then :func:`check_contract` and :meth:`Pool.check_inputs_kept`."""
    outcome = drive(argv)
    check_contract(outcome)
    pool.check_inputs_kept(outcome)
    return outcome


def write_json_lines(path: Path, records: list[Any]) -> Path:
    path.write_text("".join(json.dumps(r) + "\n" for r in records), encoding="utf-8")
    return path

"""Plugins: found through a scenario's plugins: key, from Python and through entry points;
what they register (schema types, reality kinds) and where it came from; every way a
plugin can be wrong, as one positioned line."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Iterator

import numpy as np
import pytest

import adapt
from adapt.errors import PluginError, RunError, ScenarioError
from adapt.plugins import PluginFrom, loaded_plugins
from adapt.scenario import REALITIES, load_scenario
from adapt.schemas import REGISTRY

ROOT = Path(__file__).resolve().parents[2]

CAMERA = ("camera: {fx: 130, fy: 130, cx: 79.5, cy: 59.5, width: 160, height: 120,\n"
          "         position: [0.0, -1.0, 1.5], look_at: [0.0, 1.2, 0.0]}\n"
          "world: {objects: [{name: ball, radius: 0.1, position: [0, 1], velocity: [1, 0]}]}\n")

#: A plugin registering a perceptual schema type called NAME.
SCHEMA_PLUGIN = '''
import adapt

class Counter(adapt.Schema):
    def perceive(self, frame):
        self.frames = getattr(self, "frames", 0) + 1

    def write(self, node):
        node.set("frames", getattr(self, "frames", 0))

SPEC = adapt.REGISTRY.register(adapt.SchemaSpec(
    "NAME", adapt.SchemaKind.PERCEPTUAL, "counts frames",
    factory=lambda name, params, net: Counter(name, SPEC, params, net),
    consumes=(adapt.Port("regions", "the difference regions"),),
    parameters=(adapt.Parameter("step", int, 1, "frames per count", low=1),)))
'''

#: A plugin registering a reality kind called NAME: flat frames of a colour.
REALITY_PLUGIN = '''
import numpy as np
import adapt

class Flat:
    def __init__(self, size, fps, frames, shape):
        self.size, self.fps, self.length, self.shape = size, fps, frames, shape

    def __iter__(self):
        for i in range(self.length):
            yield adapt.Frame(i, i / self.fps, np.full(self.shape, 90, np.uint8))

    def close(self):
        pass

def open_flat(reality, scenario, streams):
    w, h = scenario.camera.width, scenario.camera.height
    shape = (h, w, 3) if not reality.get("wrong_size") else (h // 2, w, 3)
    return Flat((w, h), reality.get("fps"), reality.get("frames"), shape)

adapt.REALITIES.register(adapt.RealityType(
    "NAME", "flat grey frames", open=open_flat,
    parameters=(adapt.Parameter("fps", float, 10.0, "frames per second", low=0, low_open=True),
                adapt.Parameter("frames", int, adapt.REQUIRED, "how many", low=1),
                adapt.Parameter("wrong_size", bool, False, "deliver half-height frames"))))
'''


@pytest.fixture
def unique(request: pytest.FixtureRequest) -> Iterator[str]:
    """A name no other test registers; whatever it names is taken back afterwards."""
    name = "t-" + request.node.name.replace("_", "-").lower()[:40].strip("-")
    yield name
    REGISTRY.unregister(name)
    REALITIES.unregister(name)


def scenario(folder: Path, plugins: str, rest: str = "") -> Path:
    path = folder / "s.yaml"
    path.write_text(f"plugins: {plugins}\n" + CAMERA + rest)
    return path


def test_a_plugin_next_to_the_scenario_registers_a_schema_type_with_its_origin(
        tmp_path: Path, unique: str) -> None:
    (tmp_path / "counter.py").write_text(SCHEMA_PLUGIN.replace("NAME", unique))
    path = scenario(tmp_path, "[counter.py]", f"schemas: {{{unique}: {{step: 2}}}}\n")
    sc = load_scenario(path)
    assert [p.name for p in sc.plugins] == ["counter.py"]
    assert REGISTRY.origin(unique) == "plugin counter (counter.py)"
    assert sc.schema_settings(unique) is not None
    # the plugin is an input of the run: no output may replace it
    assert tmp_path / "counter.py" in {i.path for i in sc.inputs()}
    # loaded once: a second scenario naming it reuses it (no "already registered")
    load_scenario(path)
    plugin = next(p for p in loaded_plugins() if p.name == "counter.py")
    assert plugin.found is PluginFrom.SCENARIO and plugin.registered == (f"schema type {unique}",)
    # a bad value of the plugin's parameter is positioned like a built-in one
    path.write_text(path.read_text().replace("step: 2", "step: 0"))
    with pytest.raises(ScenarioError, match=rf"s.yaml:5:\d+: schemas.{unique}.step: expected at least 1"):
        adapt.run(load_scenario(path), max_frames=1)


@pytest.mark.parametrize("code, message", [
    (None, r"plugin 'nothing_here_at_all': no module named 'nothing_here_at_all'"),
    ("raise RuntimeError('no camera attached')",
     r"plugin 'p.py' failed on import: RuntimeError: no camera attached"),
    ("import not_a_module_anywhere", r"plugin 'p.py' failed on import: No module named "
                                     r"'not_a_module_anywhere'"),
    ("def f(:\n", r"plugin 'p.py' failed on import: invalid syntax"),
    ("import adapt\nadapt.REGISTRY.register(adapt.REGISTRY.get('drive'))",
     r"plugin 'p.py' failed on import: schema type 'drive' is already registered \(built-in\)"),
    ("import adapt\nadapt.REGISTRY.register(adapt.SchemaSpec('NAME', adapt.SchemaKind.MOTOR, '', "
     "factory=print, provides=(adapt.Port('my port'),)))",
     r"plugin 'p.py' failed on import: schema type 'NAME': port 'my port': expected a name"),
    ("import adapt\nadapt.REALITIES.register(adapt.RealityType('video', '', open=print))",
     r"plugin 'p.py' failed on import: reality kind 'video' is already registered \(built-in\)"),
])
def test_a_bad_plugin_is_one_line_at_the_scenario_line(tmp_path: Path, unique: str,
                                                       code: str | None, message: str) -> None:
    if code is not None:
        (tmp_path / "p.py").write_text(code.replace("NAME", unique))
    name = "nothing_here_at_all" if code is None else "p.py"
    path = scenario(tmp_path, f"\n  - {name}")
    with pytest.raises(ScenarioError) as info:
        load_scenario(path)
    err = info.value
    assert (err.line, err.col) == (2, 5), str(err)
    assert re.search(message.replace("NAME", unique), err.message), err.message
    assert "Traceback" not in str(err)


def test_a_failing_plugin_takes_back_what_it_registered(tmp_path: Path, unique: str) -> None:
    (tmp_path / "half.py").write_text(SCHEMA_PLUGIN.replace("NAME", unique)
                                      + "\nraise ValueError('half way')\n")
    with pytest.raises(ScenarioError, match="half way"):
        load_scenario(scenario(tmp_path, "[half.py]"))
    assert unique not in REGISTRY
    # fixed, it loads
    (tmp_path / "half.py").write_text(SCHEMA_PLUGIN.replace("NAME", unique))
    load_scenario(scenario(tmp_path, "[half.py]"))
    assert unique in REGISTRY


def test_a_plugin_reality_kind_is_read_checked_and_run(tmp_path: Path, unique: str) -> None:
    (tmp_path / "flat.py").write_text(REALITY_PLUGIN.replace("NAME", unique))
    path = scenario(tmp_path, "[flat.py]", f"reality: {{kind: {unique}, frames: 3}}\n")
    sc = load_scenario(path)
    assert sc.reality.name == unique and sc.reality.get("fps") == 10.0
    result = adapt.run(sc)
    assert result.summary["frames"] == 3 and result.error is None
    for bad, message in ((f"{{kind: {unique}}}", f"reality: missing key 'frames' of reality kind '{unique}'"),
                         (f"{{kind: {unique}, frames: 0}}", "reality.frames: expected at least 1"),
                         (f"{{kind: {unique}, frame: 3}}", "reality.frame: unknown key "
                                                           "\\(did you mean 'frames'\\?\\)"),
                         ("{kind: flatt}", "reality.kind: expected one of 'synthetic', 'video', ")):
        path.write_text(path.read_text().rsplit("reality:", 1)[0] + f"reality: {bad}\n")
        with pytest.raises(ScenarioError, match=r"s\.yaml:5:\d+: " + message):
            load_scenario(path)
    # frames of the wrong size: one line naming the kind, where it came from and its line
    path.write_text(path.read_text().rsplit("reality:", 1)[0]
                    + f"reality: {{kind: {unique}, frames: 3, wrong_size: true}}\n")
    with pytest.raises(RunError, match=rf"reality kind '{unique}' \(plugin flat \(flat.py\), "
                                       r".*s\.yaml:5:10\): frame 0 is uint8 \(60, 160, 3\)"):
        adapt.run(load_scenario(path))


def test_the_python_api_loads_plugins_and_steps_a_run(tmp_path: Path, unique: str) -> None:
    (tmp_path / "flat2.py").write_text(REALITY_PLUGIN.replace("NAME", unique))
    text = CAMERA + f"reality: {{kind: {unique}, frames: 5}}\n"
    (tmp_path / "s.yaml").write_text(text)
    with pytest.raises(ScenarioError,
                       match="expected one of 'synthetic', 'video', 'camera', 'bullet', 'external'.*got"):
        adapt.load_scenario(tmp_path / "s.yaml")
    with adapt.start(tmp_path / "s.yaml", plugins=[str(tmp_path / "flat2.py")],
                     out=tmp_path / "out") as run:
        records = [next(run), next(run)]
    assert [r.index for r in records] == [0, 1]
    assert run.result is not None and run.result.summary["stopped"] == "interrupted"
    assert (tmp_path / "out" / "report.json").is_file()
    with pytest.raises(PluginError, match="plugin 'no_such_plugin_x': no module named"):
        adapt.run(tmp_path / "s.yaml", plugins=["no_such_plugin_x"])


def test_a_frame_source_from_python_replaces_the_reality() -> None:
    class Grey:
        size, fps = (160, 120), 30.0

        def __iter__(self) -> Iterator[adapt.Frame]:
            for i in range(4):
                yield adapt.Frame(i, i / 30, np.full((120, 160, 3), 100, np.uint8))

        def close(self) -> None:
            pass

    result = adapt.run(adapt.EXAMPLE, source=Grey())
    assert result.summary["frames"] == 4 and result.summary["ground_truth"] is False
    # a scenario whose frames only Python gives says so, and is told when run without them
    external = adapt.load_scenario(adapt.EXAMPLE, overrides=["reality={kind: external}"])
    assert adapt.run(external, source=Grey()).summary["frames"] == 4
    with pytest.raises(adapt.AdaptError, match=r"reality kind 'external' \(built-in\): its "
                                               r"frames come from Python: adapt.run\(scenario, source"):
        adapt.run(external)


def test_an_installed_plugin_is_found_through_its_entry_point(tmp_path: Path) -> None:
    # a distribution as pip installs it: the package and its dist-info with entry_points.txt
    site = tmp_path / "site"
    (site / "adapt_counter").mkdir(parents=True)
    (site / "adapt_counter" / "__init__.py").write_text(SCHEMA_PLUGIN.replace("NAME", "counter"))
    info = site / "adapt_counter-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: adapt-counter\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text("[adapt.schemas]\ncounter = adapt_counter\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    out = subprocess.run([sys.executable, "-m", "adapt", "schemas", "list"], env=env,
                         capture_output=True, text=True, check=True).stdout
    assert "counter (perceptual; installed counter (adapt-counter 0.1))" in out
    listed = subprocess.run([sys.executable, "-m", "adapt", "plugins", "list"], env=env,
                            capture_output=True, text=True, check=True).stdout
    assert "registered: schema type counter" in listed
    # and a scenario may use it without naming it
    (tmp_path / "s.yaml").write_text(CAMERA + "schemas: {counter: {step: 3}}\n")
    check = subprocess.run([sys.executable, "-m", "adapt", "check", str(tmp_path / "s.yaml")],
                           env=env, capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    assert "counter (installed counter (adapt-counter 0.1))" in check.stdout
    # and used by adapt run: rules put it in place
    (tmp_path / "go.soar").write_text(
        "sp {propose (state <s> ^superstate nil -^done yes) --> (<s> ^operator <o> +) "
        "(<o> ^name start)}\n"
        "sp {apply (state <s> ^operator.name start ^io.output-link <out>) --> "
        "(<out> ^instantiate <c>) (<c> ^type counter ^name c) (<s> ^done yes)}\n")
    (tmp_path / "s.yaml").write_text(CAMERA + "schemas: {counter: {step: 3}}\nrules: [go.soar]\n")
    ran = subprocess.run([sys.executable, "-m", "adapt", "run", str(tmp_path / "s.yaml"),
                          "--max-frames", "3", "--out", str(tmp_path / "out"), "--json",
                          "--quiet"], env=env, capture_output=True, text=True)
    assert ran.returncode == 0, ran.stderr
    assert json.loads(ran.stdout)["schemas"] == ["c"]
    # a broken one is one line naming it, and exit status 1
    (site / "adapt_counter" / "__init__.py").write_text("raise ImportError('needs a GPU')\n")
    bad = subprocess.run([sys.executable, "-m", "adapt", "schemas", "list"], env=env,
                         capture_output=True, text=True)
    assert bad.returncode == 1 and "Traceback" not in bad.stderr
    assert bad.stderr.strip().endswith(
        "plugin 'counter (adapt.schemas of adapt-counter 0.1)' failed on import: ImportError: needs a GPU")


def test_adapt_plugins_list_shows_reality_kinds(tmp_path: Path, unique: str) -> None:
    (tmp_path / "flat3.py").write_text(REALITY_PLUGIN.replace("NAME", unique))
    out = subprocess.run([sys.executable, "-m", "adapt", "plugins", "list", "--plugins",
                          str(tmp_path / "flat3.py")], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT)}).stdout
    assert f"reality kind {unique} (plugin flat3" in out
    assert "frames (int, [1..]; default required): how many" in out


def test_the_public_api_is_listed_and_lazy() -> None:
    code = textwrap.dedent("""
        import sys, adapt
        heavy = [m for m in ("numpy", "cv2", "pymunk", "networkx") if m in sys.modules]
        missing = [n for n in adapt.__all__ if not hasattr(adapt, n)]
        print(heavy, missing)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT)}).stdout
    assert out.strip() == "[] []"


def test_no_output_replaces_a_plugin(tmp_path: Path, unique: str) -> None:
    # the plugin sits where the run would write its figures: the run refuses before any work
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "mine.py").write_text(SCHEMA_PLUGIN.replace("NAME", unique))
    path = scenario(tmp_path, "[figures/mine.py]")
    with pytest.raises(adapt.AdaptError, match=r"plugins\[0\] \(figures/mine.py, a plugin\)"):
        adapt.run(path, out=tmp_path, max_frames=1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figures", "s.yaml"]

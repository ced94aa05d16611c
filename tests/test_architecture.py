"""Import direction between the layers, checked on the source with ``ast``.

The engine imports only the standard library (and ``adapt.errors``); vision and
imagination know nothing of rules; nothing below the CLI imports the CLI; schemas
meet each other only through percepts on their ports; the runner knows no
concrete schema type; only the scenario reader reads YAML; the CLI stays thin.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "adapt"

STDLIB = set(sys.stdlib_module_names)


def _module_of(path: Path) -> list[str]:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return parts


def imports_of(path: Path, source: str | None = None) -> set[str]:
    """Absolute names of every module ``path`` imports, relative imports resolved."""
    text = path.read_text(encoding="utf-8") if source is None else source
    tree = ast.parse(text, filename=str(path))
    found: set[str] = set()
    here = _module_of(path)
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                if node.module:
                    found.add(node.module)
                continue
            base = package[: len(package) - (node.level - 1)]
            if node.module:
                found.add(".".join([*base, node.module]))
            else:
                found.update(".".join([*base, alias.name]) for alias in node.names)
    return found


def modules_in(subpackage: str) -> list[Path]:
    return sorted((PACKAGE / subpackage).rglob("*.py"))


@pytest.mark.parametrize("path", modules_in("engine"), ids=lambda p: p.name)
def test_engine_imports_only_stdlib_and_errors(path: Path) -> None:
    for name in imports_of(path):
        top = name.split(".")[0]
        if top == "adapt":
            assert name == "adapt.errors" or name.startswith("adapt.engine"), (
                f"{path.name} imports {name}: the engine may import only adapt.errors"
            )
        else:
            assert top in STDLIB or top == "__future__", (
                f"{path.name} imports {name}: the engine imports only the standard library"
            )


@pytest.mark.parametrize(
    "sub", ["vision", "imagination"],
)
def test_vision_and_imagination_know_nothing_of_rules(sub: str) -> None:
    for path in modules_in(sub):
        for name in imports_of(path):
            assert not name.startswith(("adapt.engine", "adapt.cli", "adapt.traceview")), (
                f"{sub}/{path.name} imports {name}"
            )
            other = "imagination" if sub == "vision" else "vision"
            assert not name.startswith(f"adapt.{other}"), f"{sub}/{path.name} imports {name}"


def test_nothing_imports_the_cli() -> None:
    for path in PACKAGE.rglob("*.py"):
        if "cli" in path.relative_to(PACKAGE).parts or path.name == "__main__.py":
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.cli"), f"{path} imports {name}"


def test_geometry_errors_and_files_are_leaves() -> None:
    for leaf, allowed in (("errors.py", set()), ("files.py", {"adapt.errors"}), ("native.py", set()),
                          ("geometry.py", {"numpy", "adapt.errors"}),
                          # plugins and parameters: below every layer that registers or declares
                          ("plugins.py", {"adapt.errors"}), ("parameters.py", set())):
        for name in imports_of(PACKAGE / leaf):
            top = name.split(".")[0]
            assert top in STDLIB or top == "__future__" or name in allowed or top in allowed, (
                f"{leaf} imports {name}"
            )


@pytest.mark.parametrize("path", modules_in("figures"), ids=lambda p: p.name)
def test_figures_draw_without_knowing_the_layers(path: Path) -> None:
    # figures: NumPy, matplotlib, adapt.files and adapt.errors only, so any layer's command may draw
    for name in imports_of(path):
        top = name.split(".")[0]
        if top == "adapt":
            assert name in ("adapt.files", "adapt.errors") or name.startswith("adapt.figures"), (
                f"figures/{path.name} imports {name}"
            )
        else:
            assert top in STDLIB or top in ("__future__", "numpy", "matplotlib"), (
                f"figures/{path.name} imports {name}"
            )


def test_vision_does_not_draw_figures() -> None:
    for path in modules_in("vision"):
        for name in imports_of(path):
            assert not name.startswith(("adapt.figures", "matplotlib")), f"vision/{path.name} imports {name}"


#: What each layer above the foundations may import from adapt (prefixes).
ALLOWED = {
    # the mirror (the imagination kept in step, and the appearance it learns): no vision, no rules
    "mirror": ("adapt.mirror", "adapt.imagination", "adapt.geometry", "adapt.errors",
               "adapt.files", "adapt.native"),
    "kalman.py": (),
    # the map-aware analytic predictor: geometry from the scene's records, nothing else
    "reflection.py": ("adapt.imagination.scene",),
    "seeds.py": (),
    "frames.py": ("adapt.errors", "adapt.files", "adapt.native"),
    # the lens: a calibration's numbers and the maps that undistort frames
    "lens.py": ("adapt.errors", "adapt.frames"),
    # scenario: of the engine, only its interface (the engine names a scenario's engine: takes)
    "scenario": ("adapt.scenario", "adapt.imagination", "adapt.geometry", "adapt.errors",
                 "adapt.files", "adapt.engine.interface", "adapt.lens", "adapt.plugins",
                 "adapt.parameters"),
    "schemas": ("adapt.schemas", "adapt.engine", "adapt.vision", "adapt.imagination",
                "adapt.mirror", "adapt.geometry", "adapt.errors", "adapt.kalman",
                "adapt.frames", "adapt.scenario", "adapt.plugins", "adapt.parameters"),
    # reality: never the engine or vision (it is what perception looks at, not a perceiver)
    "reality": ("adapt.reality", "adapt.imagination", "adapt.scenario", "adapt.geometry",
                "adapt.errors", "adapt.files", "adapt.frames", "adapt.seeds", "adapt.native",
                "adapt.lens", "adapt.plugins"),
    # sweep: runs the runner, and checks a grid's cells with the runner's scenario check
    "sweep": ("adapt.sweep", "adapt.runner", "adapt.scenario", "adapt.errors", "adapt.files"),
}


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_layers_import_only_what_is_below_them(layer: str) -> None:
    target = PACKAGE / layer
    paths = [target] if target.is_file() else modules_in(layer)
    for path in paths:
        for name in imports_of(path):
            if name.split(".")[0] != "adapt" or name == "adapt":  # the version only
                continue
            assert name.startswith(ALLOWED[layer]), f"{layer}: {path.name} imports {name}"


PERCEIVING = ("engine", "vision", "imagination", "schemas", "mirror", "kalman.py")


@pytest.mark.parametrize("layer", PERCEIVING)
def test_nothing_that_perceives_can_reach_ground_truth(layer: str) -> None:
    target = PACKAGE / layer
    paths = [target] if target.is_file() else modules_in(layer)
    for path in paths:
        for name in imports_of(path):
            assert not name.startswith(("adapt.reality", "adapt.runner")), (
                f"{path} imports {name}: the perceiving side never sees the reality's truth"
            )
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            word = node.attr if isinstance(node, ast.Attribute) else (
                node.id if isinstance(node, ast.Name) else None)
            assert word not in ("truth", "ground_truth"), f"{path} reads {word}"


def test_only_the_runner_and_the_cli_open_the_reality() -> None:
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).parts
        if parts[0] in ("runner", "cli", "reality", "api.py", "__init__.py"):  # the top: API, CLI
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.reality"), f"{path} imports {name}"
            if parts[0] == "sweep":  # a sweep runs whole runs: the runner, never the reality
                continue
            assert not name.startswith("adapt.runner"), f"{path} imports {name}"


def test_only_the_cli_imports_the_sweep() -> None:
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).parts
        if parts[0] in ("sweep", "cli"):
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.sweep"), f"{path} imports {name}"


def test_the_sweep_imports_dask_only_inside_functions() -> None:
    # `import adapt.sweep` works without the optional extra; the command says how to install it
    for path in modules_in("sweep"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] if isinstance(node, ast.Import) else [
                    node.module or ""]
                assert not any(n.split(".")[0] in ("dask", "distributed") for n in names), (
                    f"sweep/{path.name} imports Dask at module level")


def test_relative_imports_are_resolved() -> None:
    path = PACKAGE / "schemas" / "network.py"
    found = imports_of(path, "from . import links\nfrom .base import Schema\nfrom ..engine import Agent\n")
    assert found == {"adapt.schemas.links", "adapt.schemas.base", "adapt.engine"}
    init = PACKAGE / "schemas" / "__init__.py"
    assert imports_of(init, "from .network import X\n") == {"adapt.schemas.network"}


# -- the integration floor -------------------------------------------------------------------


def _schema_classes() -> dict[str, set[str]]:
    """Module name -> the schema classes it defines (subclasses of Schema, directly or not)."""
    bases: dict[str, tuple[str, list[str]]] = {}
    for path in modules_in("schemas"):
        module = ".".join(_module_of(path))
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.ClassDef):
                names = [b.id if isinstance(b, ast.Name) else getattr(b, "attr", "") for b in node.bases]
                bases[node.name] = (module, names)
    found: dict[str, set[str]] = {}

    def is_schema(name: str, seen: frozenset[str] = frozenset()) -> bool:
        if name == "Schema":
            return True
        if name not in bases or name in seen:
            return False
        return any(is_schema(b, seen | {name}) for b in bases[name][1])

    for name, (module, _) in bases.items():
        if name != "Schema" and is_schema(name):
            found.setdefault(module, set()).add(name)
    return found


SCHEMA_CLASSES = _schema_classes()


def test_the_schema_types_are_found() -> None:
    names = set().union(*SCHEMA_CLASSES.values())
    assert {"SceneBackground", "ForegroundObject", "Drive", "Intercept"} <= names


@pytest.mark.parametrize("module", sorted(SCHEMA_CLASSES))
def test_no_schema_module_uses_another_schema_class(module: str) -> None:
    # schemas meet through percepts on their ports (adapt/schemas/percepts.py), never through
    # another schema's members: a schema module imports no other schema module, except the
    # class it derives from (the intercept schema drives like the drive schema)
    path = PACKAGE.parent / (module.replace(".", "/") + ".py")
    tree = ast.parse(path.read_text(encoding="utf-8"))
    derived = {b.id for node in ast.walk(tree) if isinstance(node, ast.ClassDef)
               for b in node.bases if isinstance(b, ast.Name)}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module in SCHEMA_CLASSES \
                and node.module != module:
            for alias in node.names:
                assert alias.name in SCHEMA_CLASSES[node.module] and alias.name in derived, (
                    f"{module} imports {alias.name} from {node.module}: read its percepts instead")
        elif isinstance(node, ast.Import):
            for alias in node.names:
                assert alias.name not in SCHEMA_CLASSES or alias.name == module, (
                    f"{module} imports {alias.name}")


#: What a schema may use of the network: its view of the mirror and the run, the percepts, and
#: what every schema tells it (boxes, claims, monitored objects).  Nothing that reaches another
#: schema (``ordered``, ``graph``, ``network[name]``, iteration).
SCHEMA_NETWORK_API = {"mirror", "models", "goals", "predict", "rng", "frame_interval", "reality",
                      "frame_index", "time", "decision", "actuator", "publish", "percepts",
                      "percept", "claims", "monitor_of", "note", "monitored_boxes",
                      "robot", "robot_pose", "command_robot"}
#: What the runner may use of the network besides: driving it, and reading what it publishes.
RUNNER_NETWORK_API = SCHEMA_NETWORK_API | {
    "published", "names", "listeners", "changed", "subscene", "seconds", "perceive", "perceive_spawned", "act",
    "write_input", "on_output"}


def _network_uses(path: Path) -> list[tuple[int, str]]:
    """``(line, attribute)`` of every use of a ``network``'s members (``x.network.y``,
    ``network.y``), and ``(line, "[]")`` for a subscript or iteration of a network."""
    found: list[tuple[int, str]] = []
    tree = ast.parse(path.read_text(encoding="utf-8"))

    def is_network(node: ast.expr) -> bool:
        return (isinstance(node, ast.Attribute) and node.attr == "network") or (
            isinstance(node, ast.Name) and node.id == "network")

    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and is_network(node.value):
            found.append((node.lineno, node.attr))
        elif isinstance(node, ast.Subscript) and is_network(node.value):
            found.append((node.lineno, "[]"))
        elif isinstance(node, (ast.For, ast.comprehension)) and is_network(node.iter):
            found.append((getattr(node, "lineno", 0), "[]"))
    return found


@pytest.mark.parametrize("module", sorted(SCHEMA_CLASSES))
def test_a_schema_reaches_no_other_schema_through_the_network(module: str) -> None:
    path = PACKAGE.parent / (module.replace(".", "/") + ".py")
    for line, attr in _network_uses(path):
        assert attr in SCHEMA_NETWORK_API, (
            f"{module}:{line} uses network.{attr}: a schema reads others' percepts on its ports")


@pytest.mark.parametrize("path", modules_in("runner"), ids=lambda p: p.name)
def test_the_runner_reads_the_network_through_its_api(path: Path) -> None:
    for line, attr in _network_uses(path):
        assert attr in RUNNER_NETWORK_API, (
            f"runner/{path.name}:{line} uses network.{attr}: read the published percepts")


def test_the_network_knows_no_schema_type() -> None:
    # the network joins schemas by their declared ports; only the registry lists the built-ins
    for path in modules_in("schemas"):
        if path.name == "registry.py" or ".".join(_module_of(path)) in SCHEMA_CLASSES:
            continue
        for name in imports_of(path):
            assert name not in SCHEMA_CLASSES, f"schemas/{path.name} imports {name}"


@pytest.mark.parametrize("path", modules_in("runner"), ids=lambda p: p.name)
def test_the_runner_imports_no_concrete_schema_class(path: Path) -> None:
    # the runner reads percepts (adapt.schemas.percepts) and the network's API, never a type
    for name in imports_of(path):
        assert name not in SCHEMA_CLASSES, f"runner/{path.name} imports {name}"
    text = path.read_text(encoding="utf-8")
    for classes in SCHEMA_CLASSES.values():
        for cls in classes:
            assert f"isinstance(s, {cls})" not in text and f", {cls})" not in text, (
                f"runner/{path.name} looks for {cls}")


def test_only_the_scenario_reader_imports_yaml() -> None:
    for path in PACKAGE.rglob("*.py"):
        if path.relative_to(PACKAGE).parts[0] == "scenario":
            continue
        for name in imports_of(path):
            assert name.split(".")[0] != "yaml", f"{path.relative_to(PACKAGE)} imports {name}"


#: The calls a command's argument declarations are made of (not counted as a body's lines).
_DECLARATIONS = ("add_argument", "add_parser", "set_defaults", "add_mutually_exclusive_group",
                 "add_argument_group", "add_subparsers")


def _declaration(stmt: ast.stmt) -> bool:
    if isinstance(stmt, ast.Assign):
        value: ast.expr = stmt.value
    elif isinstance(stmt, ast.Expr):
        value = stmt.value
    else:
        return False
    return (isinstance(value, ast.Call) and isinstance(value.func, ast.Attribute)
            and value.func.attr in _DECLARATIONS)


def body_lines(fn: ast.FunctionDef) -> int:
    """Source lines of a function's body: its docstring and argument declarations apart."""
    body = list(fn.body)
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        body = body[1:]
    lines: set[int] = set()
    for stmt in body:
        if not _declaration(stmt):
            lines.update(range(stmt.lineno, (stmt.end_lineno or stmt.lineno) + 1))
    return len(lines)


@pytest.mark.parametrize("path", modules_in("cli"), ids=lambda p: p.name)
def test_no_cli_function_is_over_40_lines(path: Path) -> None:
    # the CLI parses, calls and renders: logic that makes a handler long belongs in a layer
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            assert body_lines(node) <= 40, (  # type: ignore[arg-type]
                f"cli/{path.name}: {node.name} has {body_lines(node)} lines")  # type: ignore[arg-type]


def test_the_line_count_leaves_out_docstrings_and_declarations() -> None:
    fn = ast.parse('''
def f(p):
    """Doc."""
    p.add_argument("--x",
                   help="x")
    q = p.add_parser("y")
    return q
''').body[0]
    assert body_lines(fn) == 1  # type: ignore[arg-type]


@pytest.mark.parametrize("path", modules_in("soar") + [PACKAGE / "engines.py"],
                         ids=lambda p: p.name)
def test_the_soar_engine_stands_beside_the_engine(path: Path) -> None:
    # adapt.soar speaks to the kernel behind the engine's interface: it uses the engine's
    # records (symbols, WMEs, reports, the trace writer), never the other way round; only
    # its worker, run as a script in the kernel's process, imports soar_sml
    for name in imports_of(path):
        top = name.split(".")[0]
        if top == "adapt":
            allowed = ("adapt.engine", "adapt.errors", "adapt.soar")
            assert name.startswith(allowed), f"{path.name} imports {name}"
        elif top == "soar_sml":
            assert path.name == "worker.py", f"{path.name} imports soar_sml"
        else:
            assert top in STDLIB or top == "__future__", f"{path.name} imports {name}"
    if path.name == "worker.py":  # a script: nothing of adapt, so it starts fast and alone
        assert not any(n.startswith("adapt") for n in imports_of(path))


def test_nothing_but_the_engine_choice_imports_the_soar_engine() -> None:
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).parts
        if parts[0] in ("soar", "engines.py", "cli"):
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.soar"), (
                f"{path} imports {name}: layers use adapt.engines.make_agent and the interface")


#: What of the engine the runner and the schemas may use: its interface and records, the
#: trace writer (the runner's trace holds the engine's records), the parser (the own
#: engine's check of rule files).  Never an engine itself: agents come from
#: adapt.engines.make_agent and are used through adapt.engine.interface.RuleEngine.
ENGINE_SURFACE = ("adapt.engine.interface", "adapt.engine.symbols", "adapt.engine.trace",
                  "adapt.engine.parse", "adapt.engine.functions")


@pytest.mark.parametrize("path", modules_in("runner") + modules_in("schemas"),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_runner_and_the_schemas_use_the_engine_interface_only(path: Path) -> None:
    for name in imports_of(path):
        if name == "adapt.engine" or name.startswith("adapt.engine."):
            assert name in ENGINE_SURFACE, (
                f"{path.parent.name}/{path.name} imports {name}: use adapt.engine.interface")


def test_the_bullet_reality_shares_no_code_with_the_imagination() -> None:
    # another physics engine and renderer: of the imagination it reads the world's records
    # (geometry) and where the bundled textures' files are, nothing else
    for path in modules_in("reality/bullet"):
        for name in imports_of(path):
            if name.startswith("adapt.imagination"):
                assert name in ("adapt.imagination.scene", "adapt.imagination.texture"), (
                    f"reality/bullet/{path.name} imports {name}")
            assert not name.startswith(("adapt.mirror", "adapt.schemas", "adapt.runner")), (
                f"reality/bullet/{path.name} imports {name}")


def test_only_the_bullet_client_imports_pybullet() -> None:
    # `import adapt` and every other module work without the optional extra
    for path in PACKAGE.rglob("*.py"):
        if path == PACKAGE / "reality" / "bullet" / "client.py":
            continue
        for name in imports_of(path):
            assert name.split(".")[0] != "pybullet", f"{path} imports {name}"
    text = (PACKAGE / "reality" / "bullet" / "client.py").read_text(encoding="utf-8")
    assert "import pybullet" not in text  # imported inside load_pybullet, by name


# -- plugins and the public API ----------------------------------------------------------------

def test_only_the_package_and_the_cli_import_the_api() -> None:
    # adapt.api is the top of the stack, beside the CLI: no layer calls back up into it
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE)
        if rel.parts[0] == "cli" or rel.name in ("api.py", "__init__.py") and len(rel.parts) == 1:
            continue
        for name in imports_of(path):
            assert not name.startswith("adapt.api"), f"{rel} imports {name}"


def test_the_registries_hold_origins_through_the_plugins_leaf() -> None:
    # the schema and reality registries ask adapt.plugins where a name came from; nothing else
    # of adapt imports a plugin's module by name (plugins are found, never imported statically)
    users = {str(p.relative_to(PACKAGE)) for p in PACKAGE.rglob("*.py")
             if any(n == "adapt.plugins" for n in imports_of(p))}
    assert users <= {"schemas/registry.py", "scenario/kinds.py", "scenario/__init__.py",
                     "api.py", "cli/schemas.py"}, users
    for path in PACKAGE.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        assert "examples" not in {n.split(".")[0] for n in imports_of(path, text)}, path


def test_the_public_api_gives_plugins_no_concrete_schema_and_no_truth() -> None:
    # a plugin's schema meets the others only through percepts on ports, and nothing that
    # perceives sees the ground truth: adapt.__all__ offers neither a built-in schema class
    # nor anything of the reality's truth
    import adapt
    from adapt.schemas.base import Schema

    for name in adapt.__all__:
        value = getattr(adapt, name)
        if isinstance(value, type) and issubclass(value, Schema):
            assert value is Schema, f"adapt.{name} is a concrete schema class"
        module = getattr(value, "__module__", "") or ""
        assert not module.startswith("adapt.reality"), f"adapt.{name} comes from {module}"
        assert "truth" not in name.lower(), f"adapt.{name}"


@pytest.mark.parametrize("path", sorted((PACKAGE.parent / "examples").rglob("*.py")),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_examples_import_only_the_package(path: Path) -> None:
    # the examples are written as a user would: `import adapt`, nothing below it
    for name in imports_of(path):
        if name.split(".")[0] == "adapt":
            assert name == "adapt", f"examples/{path.parent.name}/{path.name} imports {name}"


@pytest.mark.parametrize("path", sorted((PACKAGE.parent / "examples").rglob("*.py")),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_examples_schemas_use_only_the_networks_api_for_schemas(path: Path) -> None:
    # a plugin's schema holds to the contract the built-in ones hold to
    for line, attr in _network_uses(path):
        assert attr in SCHEMA_NETWORK_API, (
            f"examples/{path.parent.name}/{path.name}:{line} uses network.{attr}")

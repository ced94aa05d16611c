"""``adapt run`` and ``adapt check``: run a scenario, or validate it without running.

``adapt run SCENARIO.yaml [--set KEY=VALUE ...] [--out DIR] [--seed N] [--max-frames N] [--trace-level N]``
    runs the perception-deliberation loop and writes ``report.json``,
    ``trace.jsonl``, ``mmd.mp4`` and ``figures/`` into DIR (default
    ``runs/<scenario name>``).  The rules' ``(write ...)`` text is printed as
    it happens; a progress line shows on a terminal; a short summary ends the
    run.  Ctrl-C stops the run and still writes complete outputs of the
    frames done (exit status 130).
``adapt check SCENARIO.yaml [--set KEY=VALUE ...]``
    reads the scenario, checks its schema parameters against the schema
    types and parses its rule files, and prints what it found.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from adapt.cli.exits import Exit
from adapt.cli.progress import ProgressLine
from adapt.cli.values import folder_name, seed_number
from adapt.errors import AdaptError

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add ``run`` and ``check``."""
    p = sub.add_parser("run", help="run a scenario: frames, schemas, rules, imagination",
                       description="Run SCENARIO's perception-deliberation loop frame by frame "
                       "and write its report, trace, MMD video and figures.")
    p.add_argument("scenario", metavar="SCENARIO.yaml")
    _overrides(p)
    p.add_argument("--out", metavar="DIR", type=folder_name,
                   help="output folder (default runs/<scenario name>)")
    p.add_argument("--seed", type=seed_number, default=None, metavar="N",
                   help="random seed, an integer >= 0 (default: the scenario's)")
    p.add_argument("--max-frames", type=int, default=None, metavar="N",
                   help="stop after N frames (default: the scenario's run section)")
    p.add_argument("--trace-level", type=int, default=None, choices=range(1, 6), metavar="1..5",
                   help="trace detail (default: the scenario's outputs.trace_level, 4)")
    p.add_argument("--no-video", action="store_true", help="do not write mmd.mp4")
    p.add_argument("--no-figures", action="store_true", help="do not write figures/")
    p.add_argument("--json", action="store_true", help="print the run's summary as JSON")
    p.add_argument("--quiet", action="store_true", help="print neither progress nor rule writes")
    p.set_defaults(func=_run)

    c = sub.add_parser("check", help="validate a scenario and its rule files without running it",
                       description="Read SCENARIO, check its schema parameters and parse its rule "
                       "files; errors point at file:line:col.")
    c.add_argument("scenario", metavar="SCENARIO.yaml")
    _overrides(c)
    c.add_argument("--json", action="store_true", help="print what was found as JSON")
    c.set_defaults(func=_check)


def _overrides(p: Any) -> None:
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   help="override one scenario value: a dotted key (list items by name or "
                   "index, e.g. reality.objects.ball.restitution) and a YAML value; repeatable")


class _ProgressLine(ProgressLine):
    """``frame 120/300  28.4 frames/s  3 schemas`` on a terminal, rewritten in place."""

    def __call__(self, p: Any) -> None:
        text = (f"frame {p.frame}/{p.frames}  t={p.time:6.2f} s  {p.fps:5.1f} frames/s  "
                f"{p.schemas} schema{'' if p.schemas == 1 else 's'}")
        self.show(text)


def _outputs(args: argparse.Namespace, sc: Any) -> Any:
    """The scenario's outputs with the command line's changes."""
    from dataclasses import replace

    outputs = sc.outputs
    if args.trace_level is not None:
        outputs = replace(outputs, trace_level=args.trace_level)
    if args.no_video:
        outputs = replace(outputs, video=False)
    if args.no_figures:
        outputs = replace(outputs, figures=False)
    return outputs


class _Writes:
    """The rules' ``(write ...)`` text on standard output, as it happens (the progress line
    cleared first; a closed pipe stops the echo, not the run)."""

    def __init__(self, bar: _ProgressLine | None, show: bool) -> None:
        self.bar = bar
        self.show = show

    def __call__(self, text: str) -> None:
        if not self.show:
            return
        if self.bar is not None:
            self.bar.clear()
        try:
            sys.stdout.write(text)
            sys.stdout.flush()
        except BrokenPipeError:  # the reader went away (| head): the run goes on
            self.show = False


def _run(args: argparse.Namespace) -> int:
    from adapt.runner import Runner
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario, overrides=args.overrides)
    if args.max_frames is not None and args.max_frames < 1:
        raise AdaptError(f"--max-frames must be at least 1, got {args.max_frames}")
    out = Path(args.out) if args.out else Path("runs") / Path(args.scenario).stem
    bar = _ProgressLine(sys.stderr) if sys.stderr.isatty() and not args.quiet else None
    runner = Runner(sc, out=out, seed=args.seed, max_frames=args.max_frames,
                    outputs=_outputs(args, sc), on_progress=bar,
                    on_write=_Writes(bar, not (args.quiet or args.json)))
    try:
        result = runner.run()
    finally:
        if bar is not None:
            bar.clear()
    if args.json:
        print(json.dumps(result.summary))
    else:
        for line in summary_lines(result.summary):
            print(line)
        for path in result.outputs.values():
            print(f"wrote {path}")
    return int(Exit.INTERRUPTED) if result.interrupted else int(Exit.OK)


def summary_lines(s: dict[str, Any]) -> list[str]:
    """The short summary a run ends with, from its summary (``report.json``'s)."""
    state = "interrupted after" if s["interrupted"] else "ran"
    ev = s["events"]
    lines = [f"{state} {s['frames']} frames ({s['simulated_s']:.2f} s of reality) in "
             f"{s['wall_s']:.1f} s: {s['frames_per_s']} frames/s",
             f"schemas: {', '.join(s['schemas']) or 'none'} "
             f"({ev.get('instantiated', 0)} instantiated top-down, {ev.get('spawned', 0)} spawned "
             f"bottom-up, {ev.get('rejected', 0)} commands rejected)"]
    pos, rot = s.get("camera_position_error_m"), s.get("camera_rotation_error_deg")
    if pos and rot:
        lines.append(f"camera vs truth at the end: {100 * pos['last']:.2f} cm, "
                     f"{rot['last']:.3f} deg")
    return (lines + _source_lines(s) + _goal_lines(s) + _tracking_lines(s) + _intercept_lines(s)
            + _prediction_lines(s))


def _source_lines(s: dict[str, Any]) -> list[str]:
    """What a camera did: frames dropped, the rate measured, a stall."""
    src = s.get("source")
    if not src:
        return []
    measured = src.get("fps_measured")
    rate = f"{measured:g} frames/s measured" if measured else "no rate measured"
    line = (f"{src['device']}: {src['frames_delivered']} frames taken of {src['frames_read']} "
            f"read, {src['frames_dropped']} dropped; {rate} (assumed {src['fps']:g}, "
            f"{src['clock']} clock)")
    if src.get("stalled"):
        line += f"; stalled: no frame for {src['stall_s']:g} s"
    return [line]


def _goal_lines(s: dict[str, Any]) -> list[str]:
    """What went wrong with the sight of the goals' objects (summary.goal_objects)."""
    lines = []
    for name, g in (s.get("goal_objects") or {}).items():
        if g["never_seen"]:
            lines.append(f"the goal's object {name!r} was never seen ({g['unseen_s']:g} s)")
            continue
        if g["lost"]:
            lines.append(f"the goal's object {name!r} was lost {g['lost']} time(s), "
                         f"{g['lost_s']:g} s in all (longest {g['longest_lost_s']:g} s"
                         + (", until the end)" if g["lost_at_end"] else ")"))
        if g["first_seen_s"] > 1.0:
            lines.append(f"the goal's object {name!r} was first seen after "
                         f"{g['first_seen_s']:g} s")
    return lines


def _tracking_lines(s: dict[str, Any]) -> list[str]:
    lines = []
    for name, e in (s.get("tracking_error_m") or {}).items():
        if e:
            lines.append(f"{name}: observed vs truth median {100 * e['median']:.1f} cm (p90 "
                         f"{100 * e['p90']:.1f} cm)")
    for name, e in (s.get("imagination_error_m") or {}).items():
        u = (s.get("uncorrected_error_m") or {}).get(name)
        if e:
            lines.append(f"{name}: imagined vs truth median {100 * e['median']:.1f} cm (p90 "
                         f"{100 * e['p90']:.1f} cm)"
                         + (f"; uncorrected {100 * u['median']:.1f} cm" if u else ""))
    return lines


def _intercept_lines(s: dict[str, Any]) -> list[str]:
    icpt = s.get("intercept")
    if not icpt:
        return []
    reach = "" if icpt.get("reachable") is not False else " (out of reach of this robot)"
    mine = (f"caught {icpt['object']} at t={icpt['t']:.2f} s" if icpt["caught"]
            else f"did not catch {icpt['object']}{reach}")
    line = f"intercept: {mine}"
    for key, label in (("baseline", "Kalman"), ("mapaware", "map-aware")):
        base = s.get(key)
        if base is not None:
            line += (f"; the {label} baseline's robot "
                     + (f"at t={base['t']:.2f} s" if base.get("caught") else "did not catch it"))
    return [line]


def _prediction_lines(s: dict[str, Any]) -> list[str]:
    lines = []
    for horizon, by in sorted((s.get("prediction_error_m") or {}).items()):
        m = by.get("mirror") or {}
        for kind, label in (("bounce", "with a bounce"), ("no_bounce", "without")):
            mm = m.get(f"{kind}_median")
            if mm is not None:
                beside = "".join(
                    f", {name} baseline {100 * v:.1f} cm"
                    for key, name in (("baseline", "Kalman"), ("mapaware", "map-aware"))
                    if (v := (by.get(key) or {}).get(f"{kind}_median")) is not None)
                lines.append(f"prediction {horizon} s ahead, {label}: mirror {100 * mm:.1f} cm"
                             f"{beside} (median of {m.get(kind + '_n')})")
    conf = s.get("confidence")
    if conf and conf.get("within_reach") is not None:
        lines.append(f"confident predictions ({conf['threshold']} at {conf['horizon']:g} s): "
                     f"{100 * conf['within_reach']:.0f}% of {conf['confident']} within the "
                     "catch reach")
    return lines


def _check(args: argparse.Namespace) -> int:
    from adapt.runner import check_scenario, run_length
    from adapt.scenario import load_scenario

    sc = load_scenario(args.scenario, overrides=args.overrides)
    found = check_scenario(sc)
    length = run_length(sc)
    if args.json:
        print(json.dumps(_check_json(args.scenario, found, length)))
        return 0
    for rule in found.rules:
        for w in rule.warnings:
            print(f"warning: {w}", file=sys.stderr)
    for line in _check_lines(args.scenario, found, length):
        print(line)
    return 0


def _check_json(name: str, found: Any, length: Any) -> dict[str, Any]:
    sc = found.scenario
    return {
        "scenario": name,
        "camera": {"width": sc.camera.width, "height": sc.camera.height,
                   "mount": sc.mount.kind.value},
        "world": {"walls": len(sc.scene.walls), "obstacles": len(sc.scene.obstacles),
                  "objects": [{"name": m.name, "create": m.create.value} for m in sc.objects],
                  "robot": sc.scene.robot is not None},
        "reality": sc.reality.name,
        "reality_origin": _reality_origin(sc),
        "plugins": [{"name": p.name, "module": p.module, "origin": p.origin} for p in sc.plugins],
        "schema_types": _type_origins(),
        "goals": [g.name for g in sc.goals],
        "rules": [{"file": str(r.path), "productions": r.productions,
                   "warnings": list(r.warnings)} for r in found.rules],
        "schemas": [s.type for s in sc.schemas],
        "run": {"fps": length.fps, "frames": length.frames,
                "decisions_per_frame": sc.run.decisions_per_frame},
        "seed": sc.seed,
        "engine": sc.engine.value,
    }


def _reality_origin(sc: Any) -> str:
    from adapt.scenario import REALITIES

    return REALITIES.origin(sc.reality.name) if sc.reality.name in REALITIES else "built-in"


def _type_origins() -> list[dict[str, str]]:
    from adapt.schemas import REGISTRY

    return [{"name": name, "origin": REGISTRY.origin(name)} for name in REGISTRY.names()]


def _check_lines(name: str, found: Any, length: Any) -> list[str]:
    sc = found.scenario
    objects = ", ".join(f"{m.name} ({m.create.value})" for m in sc.objects)
    lines = [f"{name}: ok",
             f"  camera {sc.camera.width}x{sc.camera.height}, {sc.mount.kind.value}; world: "
             f"{len(sc.scene.walls)} walls, {len(sc.scene.obstacles)} obstacles, objects: "
             f"{objects or 'none'}{', a robot' if sc.scene.robot else ''}",
             f"  reality: {sc.reality.name} ({_reality_origin(sc)}); {length.frames} frames at {length.fps:g} "
             f"frames/s, {sc.run.decisions_per_frame} decisions per frame; seed {sc.seed}",
             f"  goals: {', '.join(g.name for g in sc.goals) or 'none'}; schema settings: "
             f"{', '.join(s.type for s in sc.schemas) or 'none'}",
             f"  engine: {sc.engine.value}"]
    by_origin: dict[str, list[str]] = {}
    for t in _type_origins():
        by_origin.setdefault(t["origin"], []).append(t["name"])
    lines.append("  schema types: " + "; ".join(f"{', '.join(names)} ({origin})"
                                                for origin, names in by_origin.items()))
    for r in found.rules:
        lines.append(f"  rules: {r.path}: {r.productions} "
                     f"production{'' if r.productions == 1 else 's'}")
    if not found.rules:
        lines.append("  rules: none (the run will instantiate no schemas)")
    return lines

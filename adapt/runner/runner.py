"""The scenario runner: the perception-deliberation loop, frame by frame.

Each frame, in this order (paper sections 3.1-3.3, 4.1):

1. the **frame source** delivers the real image of time ``t``;
2. the **perceptual schemas** look at it (the Scene Background schema
   renders the imagination at ``t``, computes the MMD, corrects the
   synthetic camera and reports difference regions; object schemas find
   their objects);
3. the **agent** runs ``run.decisions_per_frame`` decision cycles: in each
   input phase the schema network writes the input-link, in each output
   phase it carries out the rules' commands (instantiating schemas, top-down
   from the goals or bottom-up for unexpected regions, and commanding motor
   schemas);
4. the **motor schemas** act on the reality and the imagination;
5. the **imagination** steps to the next frame's time (the object schemas'
   corrections act on every physics step);
6. the frame's record goes to ``report.json``, the trace and ``mmd.mp4``.

Ground truth, when the reality has it, is read only in step 6, by
:mod:`adapt.runner.evaluation`; nothing in steps 1-5 can see it.

The agent runs continuously across frames (one trace, one footer), and
nothing the runner keeps grows with the number of frames: the report and
the trace are streamed, the agent keeps a bounded history, and the figures'
data are decimated.  An interrupted run (Ctrl-C) or a failed one still
leaves a complete, valid report and trace of the frames done, marked as
such.
"""

from __future__ import annotations

import enum
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from adapt.engine import Agent
from adapt.engine.trace import TraceWriter
from adapt.errors import AppearanceError, RuleError, RunError
from adapt.files import FolderLock, Output, check_outputs, lock_folder, temporary_file
from adapt.frames import Frame, FrameSource, VideoSink
from adapt.geometry import Camera
from adapt.mirror import Mirror
from adapt.runner.baseline import Baseline
from adapt.runner.evaluation import Evaluation
from adapt.runner.figures import Comparison, Comparisons, Paths, Snapshot, Snapshots
from adapt.runner.inputs import run_inputs
from adapt.runner.panels import CAPTION, side_by_side
from adapt.runner.report import ReportWriter
from adapt.runner.twin import UncorrectedTwin
from adapt.scenario import Mount, OutputSettings, Scenario
from adapt.schemas import REGISTRY, Registry, SchemaEvent, SchemaNetwork
from adapt.seeds import Streams

__all__ = ["Runner", "RunResult", "Progress", "Stop", "STAGES", "AGENT_HISTORY", "OUTPUT_FOLDERS"]

#: The stages timed per frame, in loop order.
STAGES = ("reality", "perception", "decisions", "action", "physics", "outputs")

#: Operator selections, impasses and writes the agent keeps in memory.
AGENT_HISTORY = 1000

#: The folders a run fills inside its output folder.
OUTPUT_FOLDERS = ("figures", "appearance")


class Stop(enum.Enum):
    """Why a scenario run stopped: its summary's ``stopped`` and its trace footer's
    ``stop_reason`` (``docs/runner.md``)."""

    #: It ran every frame it was to run (``run.duration``, ``--max-frames``, the video's end).
    END_OF_FRAMES = "end-of-frames"
    #: A rule ran ``(halt)``.
    HALT = "halt"
    #: Ctrl-C.
    INTERRUPTED = "interrupted"
    #: An error ended it (the footer's ``error`` says which).
    ERROR = "error"


@dataclass(frozen=True, slots=True)
class Progress:
    """What a progress display shows after each frame."""

    frame: int
    frames: int
    time: float
    fps: float
    schemas: int


@dataclass
class RunResult:
    """How a run ended and where its outputs are."""

    summary: dict[str, Any]
    outputs: dict[str, Path] = field(default_factory=dict)
    interrupted: bool = False
    error: str | None = None


class Runner:
    """Runs a scenario (see the module docstring).

    Parameters
    ----------
    scenario : Scenario
    source : FrameSource, optional
        The real frames; by default the scenario's reality
        (:func:`adapt.reality.open_reality`).
    out : path, optional
        Output folder; None writes nothing.
    seed : int, optional
        Overrides the scenario's seed.
    max_frames : int, optional
        Stop after this many frames (at most the scenario's).
    outputs : OutputSettings, optional
        Overrides the scenario's ``outputs``.
    registry : Registry
        Schema types.
    on_progress, on_write : callable, optional
        Called after each frame with a :class:`Progress`, and with the text of
        every ``(write ...)`` of the rules.
    """

    def __init__(self, scenario: Scenario, *, source: FrameSource | None = None,
                 out: str | os.PathLike[str] | None = None, seed: int | None = None,
                 max_frames: int | None = None, outputs: OutputSettings | None = None,
                 registry: Registry = REGISTRY,
                 on_progress: Callable[[Progress], None] | None = None,
                 on_write: Callable[[str], None] | None = None) -> None:
        self.scenario = scenario
        self.seed = scenario.seed if seed is None else seed
        if self.seed is None:
            self.seed = 0
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise RunError(f"the seed must be an integer >= 0, got {self.seed!r}")
        self.streams = Streams(self.seed)
        self.outputs = outputs or scenario.outputs
        self.out = None if out is None else Path(out)
        limit = scenario.run.frames
        self.max_frames = limit if max_frames is None else min(limit, max_frames)
        if self.max_frames < 1:
            raise RunError(f"max_frames must be at least 1, got {max_frames}")
        self.on_progress = on_progress
        self.on_write = on_write
        self._trace: TraceWriter | None = None
        self._trace_tmp: Path | None = None
        self._lock: FolderLock | None = None
        self._check_outputs()
        if self.out is not None:  # one run per folder; what a killed run left goes
            self._lock = lock_folder(self.out, "--out", OUTPUT_FOLDERS)
        try:
            if source is None:
                from adapt.reality import open_reality

                source = open_reality(scenario, streams=self.streams)
            self.source = source
            w, h = source.size
            cam = scenario.camera
            if (w, h) != (cam.width, cam.height):
                raise RunError(f"the reality's frames are {w}x{h} but the scenario's camera is "
                               f"{cam.width}x{cam.height} ({scenario.where('camera.width').location}); "
                               "make them the same size")
            self.fps = float(source.fps)
            self.mirror = Mirror(scenario.scene, cam, seed=self.seed,
                                 camera_follows_robot=self._mount() if scenario.mount.kind is Mount.ROBOT
                                 else None)
            if scenario.appearance is not None:
                try:
                    self.mirror.load_appearance(scenario.appearance)
                except AppearanceError as exc:
                    raise scenario.where("world.appearance").error(str(exc)) from None
            self.network = SchemaNetwork(
                self.mirror, registry=registry, settings=scenario.schemas,
                models={m.name: m for m in scenario.objects}, goals=scenario.goals,
                actuator=getattr(source, "robot", None), predict=scenario.predict,
                rng=self.streams.generator("ensemble"), frame_interval=1.0 / self.fps,
                reality=scenario.reality.kind.value)
            self.truth = getattr(source, "truth", None)
            self.evaluation = Evaluation(scenario, self.truth, self.fps)
            self.twin = UncorrectedTwin(scenario.scene, seed=self.seed)
            self.baselines: dict[str, Baseline] = {}
            self.events: dict[str, int] = {}
            self.writes: list[str] = []
            self.stage_s = {s: 0.0 for s in STAGES}
            self.mmd_ms: list[float] = []
            self.frames_done = 0
            self.snapshots = Snapshots()
            self.comparisons = Comparisons()
            self.series = Paths()
            self._last_path_kept = -math.inf
            self.agent = self._agent()
            self.network.listeners.append(self._on_event)
        except BaseException:
            self.close()
            raise

    # -- set-up ----------------------------------------------------------------------------

    def _mount(self) -> Callable[[tuple[float, float], float], Camera]:
        sc = self.scenario
        base = sc.camera

        def follow(position: tuple[float, float], heading: float) -> Camera:
            p, t = sc.mount.world_pose(position, heading)
            return Camera.look_at(fx=base.fx, fy=base.fy, cx=base.cx, cy=base.cy,
                                  width=base.width, height=base.height, position=p,
                                  look_at=t, roll_deg=sc.mount.roll_deg)

        return follow

    def _paths(self) -> dict[str, Path]:
        if self.out is None:
            return {}
        o = self.outputs
        paths = {}
        if o.report:
            paths["report"] = self.out / "report.json"
        if o.trace:
            paths["trace"] = self.out / "trace.jsonl"
        if o.video:
            paths["video"] = self.out / "mmd.mp4"
        if o.figures:
            paths["figures"] = self.out / "figures"
        paths["appearance"] = self.out / "appearance"  # written when the run learned a look
        return paths

    def _check_outputs(self) -> None:
        """Refuse, before any work, an output folder that cannot be written or an output --
        a file, or any file of ``figures/`` and ``appearance/`` -- that would replace
        anything the run reads (:func:`adapt.files.check_outputs`,
        :func:`adapt.runner.inputs.run_inputs`)."""
        if self.out is None:
            return
        if self.out.exists() and not self.out.is_dir():
            raise RunError(f"--out {str(self.out)!r} is a file; expected a folder")
        suffixes = {"report": (".json",), "trace": (".jsonl",), "video": (".mp4",)}
        check_outputs([Output(f"the {name} output", path, suffixes.get(name, ()),
                              folder=name in OUTPUT_FOLDERS, remedy="choose another --out folder")
                       for name, path in self._paths().items()], run_inputs(self.scenario))

    def close(self) -> None:
        """Release the output folder; drop the trace of a run that never ran.  :meth:`run`
        calls it when it ends."""
        if self._trace is not None:
            self._trace.close()
            self._trace = None
            if self._trace_tmp is not None:
                self._trace_tmp.unlink(missing_ok=True)
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    def _agent(self) -> Agent:
        trace = None
        paths = self._paths()
        if "trace" in paths:
            target = paths["trace"]
            target.parent.mkdir(parents=True, exist_ok=True)
            self._trace_tmp = temporary_file(target)
            trace = TraceWriter(self._trace_tmp, level=self.outputs.trace_level,
                                files=[str(r.path) for r in self.scenario.rules], seed=self.seed)
            self._trace = trace
        agent = Agent(seed=self.streams.integer("agent"), trace=trace,
                      trace_level=self.outputs.trace_level, history=AGENT_HISTORY)
        for rf in self.scenario.rules:
            try:
                agent.load_file(rf.path)
            except RuleError as exc:
                raise type(exc)(f"{exc.message} (a rule file of the scenario, "
                                 f"{rf.source.location}: {rf.source.path})", file=exc.file,
                                 line=exc.line, col=exc.col, source_line=exc.source_line) from None
        agent.on_input(self.network.write_input)
        agent.on_output(self.network.on_output)
        agent.on_write(self._on_write)
        return agent

    def _on_write(self, text: str) -> None:
        self.writes.append(text)
        if len(self.writes) > 200:
            del self.writes[:100]
        if self.on_write is not None:
            self.on_write(text)

    def _on_event(self, event: SchemaEvent) -> None:
        self.events[event.kind] = self.events.get(event.kind, 0) + 1
        if event.kind == "spawned":
            self.snapshots.spawned(max(event.frame, 0))
        if event.kind == "created" and event.schema in self.network:
            schema = self.network[event.schema]
            ball = getattr(schema, "ball", None)
            model = self.scenario.objects and {m.name: m for m in self.scenario.objects}.get(
                event.data.get("body", ""))
            if model:
                ball = model.ball  # the uncorrected twin keeps the model's own parameters
            if ball is not None:
                self.twin.create(ball, event.data["position"], event.data["velocity"])
                self.comparisons.created_at(ball.name, max(event.frame, 0), self.fps)
        if self._trace is not None:
            self._trace.event("schema", event.as_json())

    # -- the loop ------------------------------------------------------------------------------

    def run(self) -> RunResult:
        """Run the loop to the end (or the interrupt); write and return the outputs; release
        the output folder."""
        try:
            return self._loop()
        finally:
            self.close()

    def _loop(self) -> RunResult:
        paths = self._paths()
        report = None
        if "report" in paths:
            report = ReportWriter(paths["report"], {
                "scenario": str(self.scenario.path) if self.scenario.path else None,
                "seed": self.seed, "fps": self.fps, "reality": self.scenario.reality.kind.value,
                "frames_planned": self.max_frames})
        video = None
        started = time.perf_counter()
        interrupted = False
        error: str | None = None
        try:
            frames = iter(self.source)
            while self.frames_done < self.max_frames:
                t0 = time.perf_counter()
                frame = next(frames, None)
                if frame is None:
                    break
                self._check_frame(frame)
                self.stage_s["reality"] += time.perf_counter() - t0
                record = self._step(frame)
                t5 = time.perf_counter()
                if report is not None:
                    report.frame(record)
                if "video" in paths:
                    if video is None:
                        w, h = self.source.size
                        video = VideoSink(paths["video"], self.fps, (3 * w, h + CAPTION))
                    video.write(self._panel(frame))
                if self._trace is not None:
                    self._trace.event("frame", self._frame_trace(record))
                    if self.network.changed:
                        self._trace.event("network", {"d": self.agent.decisions,
                                                      "frame": frame.index,
                                                      **self.network.subscene()})
                    bg = self.network.background
                    look = None if bg is None else bg.appearance_record(frame.index)
                    if look is not None:
                        self._trace.event("appearance", {"d": self.agent.decisions, **look})
                    self._trace.flush()
                self.network.changed = False
                self.stage_s["outputs"] += time.perf_counter() - t5
                self.frames_done += 1
                if self.agent.halted:
                    break
                if self.on_progress is not None:
                    wall = time.perf_counter() - started
                    self.on_progress(Progress(self.frames_done, self.max_frames, frame.time,
                                              self.frames_done / wall if wall > 0 else 0.0,
                                              len(self.network)))
        except KeyboardInterrupt:
            interrupted = True
        except BaseException as exc:
            error = f"{type(exc).__name__}: {exc}"
            self._finish(report, video, time.perf_counter() - started, False, error, paths)
            raise
        finally:
            self.source.close()
        result = self._finish(report, video, time.perf_counter() - started, interrupted, error,
                              paths)
        return result

    def _check_frame(self, frame: Frame) -> None:
        img = frame.image
        w, h = self.source.size
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3 or img.shape[:2] != (h, w):
            raise RunError(f"frame {frame.index} is {img.dtype} {tuple(img.shape)}; expected "
                           f"uint8 BGR {h}x{w}x3 like the camera")

    def _step(self, frame: Frame) -> dict[str, Any]:
        stage = self.stage_s
        t1 = time.perf_counter()
        camera = self.mirror.camera
        self.network.perceive(frame)
        after = self.comparisons.wants(frame.index)
        if after is not None and self.out is not None and self.outputs.figures:
            self._compare(frame, camera, after)
        bg = self.network.background
        if bg is not None:
            self.mmd_ms.append(bg.ms)
            if len(self.mmd_ms) > 4096:
                del self.mmd_ms[: len(self.mmd_ms) - 2048]
        t2 = time.perf_counter()
        self.agent.run(self.scenario.run.decisions_per_frame, footer=False)
        t3 = time.perf_counter()
        self.network.act(frame.time)
        t4 = time.perf_counter()
        record = self._record(frame)  # the imagination as it stands at the frame's time
        t5 = time.perf_counter()
        self.mirror.step_to(frame.time + 1.0 / self.fps)
        self.twin.step_to(frame.time + 1.0 / self.fps)
        t6 = time.perf_counter()
        stage["perception"] += t2 - t1
        stage["decisions"] += t3 - t2
        stage["action"] += t4 - t3
        stage["physics"] += t6 - t5
        stage["outputs"] += t5 - t4
        self._keep(frame, record)
        return record

    def _compare(self, frame: Frame, camera: Camera, after: float) -> None:
        """Keep, for ``correction.png``, this frame's differences from the uncorrected twin and
        from the mirror (both through the frame's ``H_e``, on one crop around the object)."""
        bg = self.network.background
        created = self.comparisons.created
        if bg is None or bg.synthetic is None or created is None:
            return
        robot = self.scenario.scene.robot
        also = () if robot is None else tuple(
            b for b in self.mirror.world.snapshot().bodies if b.name == robot.name)
        twin = self.twin.render(camera, self.mirror.renderer, also=also).image
        uncorrected = bg.difference_with(frame.image, twin)
        corrected = bg.difference_with(frame.image, bg.synthetic)
        if uncorrected is None or corrected is None:
            return
        name = created[0]
        found = [self._ball_box(camera, p, name) for p in
                 (self.twin.positions().get(name),
                  self.mirror.world.position(name) if self.mirror.has_body(name) else None)]
        found.append(self._sighting_box(name))
        boxes = [b for b in found if b is not None]
        if not boxes:
            return  # the object is out of view: nothing to compare
        h, w = frame.image.shape[:2]
        x, y, cw, ch = _crop(boxes, w, h)
        self.comparisons.add(Comparison(
            frame.index, frame.time, after, frame.image[y:y + ch, x:x + cw].copy(),
            np.asarray(uncorrected[y:y + ch, x:x + cw], np.float32),
            np.asarray(corrected[y:y + ch, x:x + cw], np.float32)))

    def _ball_box(self, camera: Camera, position: tuple[float, float] | None,
                  name: str) -> tuple[int, int, int, int] | None:
        """The image box of a ball of object ``name`` at ``position`` (None: behind the
        camera or off the image)."""
        if position is None:
            return None
        radius = next((b.radius for b in self.twin.world.balls if b.name == name), None)
        if radius is None:
            return None
        point = np.array([[position[0], position[1], radius]])
        depth = float(camera.to_camera(point)[0, 2])
        if depth <= 1e-3:
            return None
        u, v = camera.project(point)[0]
        r = camera.fx * radius / depth
        w, h = camera.size
        if not (-r < u < w + r and -r < v < h + r):
            return None
        return int(u - r), int(v - r), int(2 * r) + 1, int(2 * r) + 1

    def _sighting_box(self, name: str) -> tuple[int, int, int, int] | None:
        from adapt.schemas.foreground import ForegroundObject

        for s in self.network.ordered():
            if isinstance(s, ForegroundObject) and s.object_name == name and \
                    s.last is not None and s.misses == 0:
                return s.last.bbox
        return None

    def _keep(self, frame: Frame, record: dict[str, Any]) -> None:
        """Data for the figures: a snapshot of this frame's images, a point of each path."""
        bg = self.network.background
        res = None if bg is None else bg.result
        err = math.nan if bg is None else bg.pixel_error
        self.snapshots.add(Snapshot(
            frame.index, frame.time, frame.image, None if bg is None else bg.synthetic,
            None if res is None else res.matches.synthetic_points[res.alignment.inliers],
            None if res is None else res.warped, None if res is None else res.mask,
            None if res is None else res.difference, err,
            () if bg is None else tuple(r.bbox for r in bg.regions if not r.expected),
            tuple(self.network.monitored_boxes())))
        pose = self.mirror.robot_pose()
        self.series.add(record, err, None if pose is None else pose[0])
        if frame.time - self._last_path_kept >= 1.0:
            from adapt.schemas.foreground import ForegroundObject

            for s in self.network.ordered():
                pred = s.prediction if isinstance(s, ForegroundObject) else None
                if pred is not None and abs(pred.time - frame.time) < 0.5 / self.fps:
                    self.series.predicted_path(pred.time, pred.trajectory.positions[::3])
                    self._last_path_kept = frame.time
                    break

    # -- records ---------------------------------------------------------------------------------

    def _objects(self) -> tuple[dict[str, dict[str, Any]], dict[str, Any], dict[str, Any],
                                dict[str, Any], dict[str, Any]]:
        """Per object: observed and imagined positions, the mirror's predictions, the
        predicted contacts, the baseline's predictions and the parameter estimates."""
        from adapt.schemas.foreground import ForegroundObject

        out: dict[str, dict[str, Any]] = {}
        preds: dict[str, Any] = {}
        contacts: dict[str, Any] = {}
        baseline: dict[str, Any] = {}
        params: dict[str, Any] = {}
        for m in self.scenario.objects:
            out[m.name] = {"observed": None, "imagined": None}
        robot = self.scenario.scene.robot
        for s in self.network.ordered():
            if not isinstance(s, ForegroundObject):
                continue
            name = s.object_name
            o = s.observed()
            out.setdefault(name, {"observed": None, "imagined": None})
            out[name]["observed"] = None if o is None else [round(o[0], 4), round(o[1], 4)]
            if s.estimator is not None:
                params[name] = {k: e.as_json() for k, e in s.estimator.estimates().items()}
            if s.prediction is not None:
                preds[name] = [h.as_json() for h in s.prediction.horizons]
                contacts[name] = s.prediction.contacts_json()
            if s.ball is not None:
                b = self.baselines.get(name)
                if b is None:
                    from adapt.imagination.predict import intercept_reach

                    b = self.baselines[name] = Baseline(
                        robot, reach=0.0 if robot is None else intercept_reach(s.ball, robot),
                        horizons=self.scenario.predict.horizons, dt=1.0 / self.fps,
                        scene=self.scenario.scene)
                sighting = s.last.position if s.last is not None and s.misses == 0 else None
                b.step(self.network.time, sighting)
                baseline[name] = b.predictions()
        for ball in self.mirror.scene.balls:
            if self.mirror.has_body(ball.name):
                p = self.mirror.world.position(ball.name)
                out.setdefault(ball.name, {"observed": None, "imagined": None})
                out[ball.name]["imagined"] = [round(p[0], 4), round(p[1], 4)]
        return out, preds, contacts, baseline, params

    def _record(self, frame: Frame) -> dict[str, Any]:
        bg = self.network.background
        objects, preds, contacts, baseline, params = self._objects()
        record: dict[str, Any] = {
            "index": frame.index, "t": round(frame.time, 6),
            "schemas": self.network.names,
            "unexpected_regions": 0 if bg is None else sum(not r.expected for r in bg.regions),
            "objects": objects,
            "predictions": {name: preds.get(name, []) for name in objects},
            "contacts": contacts,
            "baseline": baseline,
            "parameters": params,
        }
        if bg is not None:
            record["mmd"] = {"aligned": bg.result is not None and bg.result.aligned,
                             "trusted": bg.trusted,
                             "pixel_error": None if math.isnan(bg.pixel_error)
                             else round(bg.pixel_error, 4),
                             "inliers": 0 if bg.result is None else bg.result.n_inliers,
                             "regions": len(bg.regions), "ms": round(bg.ms, 2)}
        pose = self.mirror.robot_pose()
        target = self.evaluation.target
        base_robot = None
        sim = None if target is None or target not in self.baselines \
            else self.baselines[target].robot
        if sim is not None:
            base_robot = tuple(float(v) for v in sim.position)
        if pose is not None:
            record["robot"] = {"odometry": [round(pose[0][0], 4), round(pose[0][1], 4)],
                               "heading": round(pose[1], 4)}
            if base_robot is not None:
                record["robot"]["baseline"] = [round(base_robot[0], 4), round(base_robot[1], 4)]
        uncorrected = self.twin.positions()
        record["uncorrected"] = {n: [round(p[0], 4), round(p[1], 4)] for n, p in uncorrected.items()}
        self.evaluation.add(frame.index, frame.time, record, self.mirror.camera,
                            uncorrected=uncorrected, baseline_robot=base_robot)
        return record

    def _frame_trace(self, record: dict[str, Any]) -> dict[str, Any]:
        bg = self.network.background
        out = {"d": self.agent.decisions, "frame": record["index"], "t": record["t"],
               "schemas": record["schemas"], "unexpected_regions": record["unexpected_regions"],
               "objects": record["objects"]}
        if "mmd" in record:
            out["mmd"] = record["mmd"]
        if bg is not None:
            out["regions"] = [r.as_json() for r in bg.regions]
        return out

    def _panel(self, frame: Frame) -> np.ndarray:
        bg = self.network.background
        monitored = self.network.monitored_boxes()
        unexpected = [] if bg is None else [r.bbox for r in bg.regions if not r.expected]
        note = ""
        if bg is not None and not math.isnan(bg.pixel_error):
            note = f"camera error {bg.pixel_error:.2f} px"
        return side_by_side(frame.image, None if bg is None else bg.synthetic,
                            None if bg is None or bg.result is None else bg.result.difference,
                            monitored, unexpected, frame=frame.index, time=frame.time, note=note)

    # -- the end -----------------------------------------------------------------------------------

    def stop(self, interrupted: bool, error: str | None) -> Stop:
        """Why the run stopped."""
        if error is not None:
            return Stop.ERROR
        if interrupted:
            return Stop.INTERRUPTED
        return Stop.HALT if self.agent.halted else Stop.END_OF_FRAMES

    def summary(self, wall: float, interrupted: bool, error: str | None) -> dict[str, Any]:
        """The run's summary (``report.json``'s ``summary``)."""
        n = max(self.frames_done, 1)
        total = sum(self.stage_s.values())
        out: dict[str, Any] = {
            "frames": self.frames_done,
            "simulated_s": round(self.frames_done / self.fps, 4),
            "wall_s": round(wall, 3),
            "frames_per_s": round(self.frames_done / wall, 2) if wall > 0 else None,
            "interrupted": interrupted,
            "error": error,
            "stopped": self.stop(interrupted, error).value,
            "decisions": self.agent.decisions,
            "halted": self.agent.halted,
            "schemas": self.network.names,
            "events": dict(sorted(self.events.items())),
            "stage_ms": {k: round(1000.0 * v / n, 3) for k, v in self.stage_s.items()},
            "stage_share": {k: round(v / total, 4) if total > 0 else 0.0
                            for k, v in self.stage_s.items()},
            "schema_ms": {k: round(1000.0 * v / n, 3) for k, v in sorted(self.network.seconds.items())},
            "mmd_ms_median": round(float(np.median(self.mmd_ms)), 3) if self.mmd_ms else None,
            "rollouts": self._rollouts(),
            "parameters": self._estimates(),
            "writes": "".join(self.writes[-20:]),
        }
        out.update(self.evaluation.summary())
        return out

    def _estimates(self) -> dict[str, Any]:
        """The object schemas' parameter estimates at the end."""
        from adapt.schemas.foreground import ForegroundObject

        return {s.object_name: {k: e.as_json() for k, e in s.estimator.estimates().items()}
                for s in self.network.ordered()
                if isinstance(s, ForegroundObject) and s.estimator is not None}

    def _rollouts(self) -> dict[str, Any]:
        """How fast the object schemas' predictions ran: seconds of imagination rolled out
        per wall-clock second (times real time)."""
        sim = wall = 0.0
        for s in self.network.ordered():
            pred = getattr(s, "predictor", None)
            if pred is not None:
                sim += pred.simulated_s
                wall += pred.wall_s
        return {"simulated_s": round(sim, 3), "wall_s": round(wall, 4),
                "times_real_time": round(sim / wall, 1) if wall > 0 else None}

    def _finish(self, report: ReportWriter | None, video: VideoSink | None, wall: float,
                interrupted: bool, error: str | None, paths: dict[str, Path]) -> RunResult:
        summary = self.summary(wall, interrupted, error)
        written: dict[str, Path] = {}
        if video is not None:
            video.close()
            written["video"] = video.path
        if self._trace is not None:
            # the summary before the footer: readers take the footer as the trace's last record
            self._trace.event("summary", {"d": self.agent.decisions, **summary})
            # the footer says why the run stopped, not why the agent's last slice of
            # decisions did (always "max-decisions", the frame's decisions done)
            self._trace.footer({**self.agent.report().to_dict(),
                                "stop_reason": summary["stopped"]}, wall, error)
            self._trace.close()
            assert self._trace_tmp is not None
            os.replace(self._trace_tmp, paths["trace"])
            self._trace = None
            written["trace"] = paths["trace"]
        if report is not None:
            written["report"] = report.close(summary)
        bg = self.network.background
        if "appearance" in paths and bg is not None and bg.learn_passes:
            self.mirror.save_appearance(paths["appearance"])
            written["appearance"] = paths["appearance"]
        if "figures" in paths and self.frames_done > 0 and error is None:
            from adapt.runner.figures import write_figures

            written.update(write_figures(self, paths["figures"]))
        return RunResult(summary, written, interrupted, error)


def _crop(boxes: list[tuple[int, int, int, int]], width: int, height: int,
          least: int = 96) -> tuple[int, int, int, int]:
    """A window ``(x, y, w, h)`` of the image holding every box with a margin, at least
    ``least`` pixels a side (the whole image when there is no box)."""
    if not boxes:
        return 0, 0, width, height
    x0 = min(b[0] for b in boxes)
    y0 = min(b[1] for b in boxes)
    x1 = max(b[0] + b[2] for b in boxes)
    y1 = max(b[1] + b[3] for b in boxes)
    pad = max(max(b[2], b[3]) for b in boxes)
    x0, y0, x1, y1 = x0 - pad, y0 - pad, x1 + pad, y1 + pad
    side_w, side_h = max(x1 - x0, least), max(y1 - y0, least)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    x = int(min(max(cx - side_w / 2, 0), max(width - side_w, 0)))
    y = int(min(max(cy - side_h / 2, 0), max(height - side_h, 0)))
    return x, y, int(min(side_w, width)), int(min(side_h, height))

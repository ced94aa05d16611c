"""The scenario runner: the perception-deliberation loop, frame by frame.

Each frame, in this order (paper sections 3.1-3.3, 4.1):

1. the **frame source** delivers the real image of time ``t``;
2. the **perceptual schemas** look at it, providers first, and publish their
   percepts (the Scene Background schema renders the imagination at ``t``,
   computes the MMD, corrects the synthetic camera and reports difference
   regions; object schemas find their objects);
3. the **agent** runs ``run.decisions_per_frame`` decision cycles: in each
   input phase the schema network writes the input-link, in each output
   phase it carries out the rules' commands (instantiating schemas, top-down
   from the goals or bottom-up for unexpected regions, and commanding motor
   schemas); a perceptual schema spawned bottom-up in them looks at the
   frame too (:meth:`SchemaNetwork.perceive_spawned
   <adapt.schemas.network.SchemaNetwork.perceive_spawned>`);
4. the **motor schemas** act on the reality and the imagination;
5. the **baselines** step on the same sightings, and the frame's typed
   record (:class:`~adapt.runner.record.FrameRecord`: the imagination as it
   stands at ``t``) goes to the listeners in order: the evaluation, then the
   report, the trace, the MMD video and the figures' collector;
6. the **imagination** (and the uncorrected twin beside it) steps to the
   next frame's time (the object schemas' corrections act on every physics
   step).

Who may write what: the schemas write the input-link, the imagination
(through the mirror) and their own percepts; the agent writes working
memory; the loop alone makes the record and steps the worlds; a listener
only reads the record.  Ground truth, when the reality has it, is read only
in step 5, by :mod:`adapt.runner.evaluation`; nothing in steps 1-4 can see
it.

The agent runs continuously across frames (one trace, one footer), and
nothing the runner keeps grows with the number of frames: the report and
the trace are streamed, the agent keeps a bounded history, and the figures'
data are decimated.  An interrupted run (Ctrl-C) or a failed one still
leaves a complete, valid report and trace of the frames done, marked as
such; when the rule engine fails (a rule's action, a crash of the Soar
kernel's process) the :class:`~adapt.errors.EngineError` raised says so and
names them.  The agent is made on the scenario's engine (``engine:``) and
used only through the engine interface
(:class:`~adapt.engine.interface.RuleEngine`).
"""

from __future__ import annotations

import enum
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Generator, Iterator, Mapping

import numpy as np

from adapt.errors import AppearanceError, EngineError, RunError
from adapt.files import FolderLock, Output, check_outputs, lock_folder
from adapt.frames import Actuator, Frame, FrameSource, SourceStatus
from adapt.geometry import Camera
from adapt.lens import undistorted
from adapt.mirror import Mirror
from adapt.runner.agent import AGENT_HISTORY, RuleEngine, make_agent
from adapt.runner.baseline import BaselineFactory, BaselineSet, default_baselines
from adapt.runner.check import check_scenario, planned_frames
from adapt.runner.evaluation import Evaluation
from adapt.runner.figures import FigureCollector, write_figures
from adapt.runner.inputs import run_inputs
from adapt.runner.panels import VideoOutput
from adapt.runner.record import FrameListener, FrameRecord, RobotPose, TrackedObject
from adapt.runner.report import ReportOutput
from adapt.runner.sightings import GoalSightings
from adapt.runner.summary import STAGES, RunStats
from adapt.runner.trace import TraceOutput
from adapt.runner.twin import UncorrectedTwin
from adapt.scenario import Mount, OutputSettings, Scenario
from adapt.schemas import REGISTRY, EventKind, Registry, SchemaEvent, SchemaNetwork
from adapt.schemas.percepts import BackgroundPercept, ObjectPercept
from adapt.seeds import Streams

if TYPE_CHECKING:  # pragma: no cover
    from adapt.reality import GroundTruth

__all__ = ["Runner", "RunResult", "Progress", "Stop", "STAGES", "AGENT_HISTORY", "OUTPUT_FOLDERS"]

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
    #: The camera delivered no frame for ``reality.stall_s`` seconds.
    STALLED = "stalled"


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
        (:func:`adapt.reality.open_reality`).  Its optional ``robot`` (an
        :class:`~adapt.frames.Actuator`) is the real robot the motor schemas
        drive, and its optional ``truth`` the ground truth the evaluation reads.
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
    listeners : sequence of FrameListener
        More listeners on the frame records, after the run's own.
    baselines : mapping of str to BaselineFactory
        More baselines beside ``kalman``, by name: each makes an
        :class:`~adapt.runner.baseline.ObjectBaseline` for an object from a
        :class:`~adapt.runner.baseline.BaselineSetup`; they step on the same sightings,
        are scored by the evaluation like the Kalman baseline and reported under their name.

    Attributes
    ----------
    result : RunResult or None
        How the run ended, once :meth:`run` returned or :meth:`frames` ended.
    """

    def __init__(self, scenario: Scenario, *, source: FrameSource | None = None,
                 out: str | os.PathLike[str] | None = None, seed: int | None = None,
                 max_frames: int | None = None, outputs: OutputSettings | None = None,
                 registry: Registry = REGISTRY,
                 on_progress: Callable[[Progress], None] | None = None,
                 on_write: Callable[[str], None] | None = None,
                 listeners: tuple[FrameListener, ...] = (),
                 baselines: Mapping[str, BaselineFactory] | None = None) -> None:
        if max_frames is not None and max_frames < 1:
            raise RunError(f"max_frames must be at least 1, got {max_frames}")
        check_scenario(scenario, registry)
        self.scenario = scenario
        self.seed: int = seed if seed is not None else scenario.seed or 0
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise RunError(f"the seed must be an integer >= 0, got {self.seed!r}")
        self.streams = Streams(self.seed)
        self.outputs = outputs or scenario.outputs
        self.out = None if out is None else Path(out)
        self.on_progress = on_progress
        self.on_write = on_write
        self.trace: TraceOutput | None = None
        self._engine: RuleEngine | None = None  # to close: the Soar kernel's process
        self.result: RunResult | None = None
        self._lock: FolderLock | None = None
        self._check_outputs()
        if self.out is not None:  # one run per folder; what a killed run left goes
            self._lock = lock_folder(self.out, "--out", OUTPUT_FOLDERS)
        try:
            if source is None:
                from adapt.reality import open_reality

                source = open_reality(scenario, streams=self.streams)
            self.source = undistorted(source, scenario.lens)  # perception sees ideal frames
            self.robot, self.truth = _extras(source)
            self._check_size()
            self.fps = float(source.fps)
            self.max_frames = planned_frames(scenario.run, source, self.fps, max_frames)
            self.mirror = self._mirror()
            self.network = SchemaNetwork(
                self.mirror, registry=registry, settings=scenario.schemas,
                models={m.name: m for m in scenario.objects}, goals=scenario.goals,
                actuator=self.robot, predict=scenario.predict,
                rng=self.streams.generator("ensemble"), frame_interval=1.0 / self.fps,
                reality=scenario.reality.kind)
            self.twin = UncorrectedTwin(scenario.scene, seed=self.seed)
            self.baselines: dict[str, BaselineSet] = default_baselines(
                scenario.scene.robot, horizons=scenario.predict.horizons, dt=1.0 / self.fps,
                scene=scenario.scene)
            for name, factory in (baselines or {}).items():
                if name in self.baselines or not name or not isinstance(name, str):
                    raise RunError(f"a baseline called {name!r} is already in the run; "
                                   "choose another name")
                self.baselines[name] = BaselineSet(
                    name, factory, robot=scenario.scene.robot, horizons=scenario.predict.horizons,
                    dt=1.0 / self.fps, scene=scenario.scene)
            self.evaluation = Evaluation(scenario, self.truth, self.fps, tuple(self.baselines))
            self.stats = RunStats()
            self.frames_done = 0
            self._events: list[SchemaEvent] = []
            self._created: list[SchemaEvent] = []
            self.agent: RuleEngine = make_agent(
                scenario, seed=self.streams.integer("agent"), history=AGENT_HISTORY)
            self._engine = self.agent
            self.trace = self._trace(self.agent)
            self.agent.on_input(self.network.write_input)
            self.agent.on_output(self.network.on_output)
            self.agent.on_write(self._on_write)
            self.network.listeners.append(self._on_event)
            self.report: ReportOutput | None = None
            self.video: VideoOutput | None = None
            self.figures: FigureCollector | None = None
            goal_objects = [str(v) for g in scenario.goals for k, v in g.attributes
                            if k == "object" and str(v) in {m.name for m in scenario.objects}]
            self.sightings = GoalSightings(goal_objects, self.fps)
            self.listeners: list[FrameListener] = [self.evaluation, self.sightings]
            self.extra = tuple(listeners)
        except BaseException:
            self.close()
            raise

    # -- set-up ----------------------------------------------------------------------------

    def _mirror(self) -> Mirror:
        sc = self.scenario
        base = sc.camera

        def follow(position: tuple[float, float], heading: float) -> Camera:
            return sc.mount.camera_at(base, position, heading)

        mirror = Mirror(sc.scene, base, seed=self.seed,
                        camera_follows_robot=follow if sc.mount.kind is Mount.ROBOT else None)
        if sc.appearance is not None:
            try:
                mirror.load_appearance(sc.appearance)
            except AppearanceError as exc:
                raise sc.where("world.appearance").error(str(exc)) from None
        return mirror

    def _reality(self) -> str:
        """``the reality`` or, for a plugin's kind, ``reality kind 'x' (its origin) at file:line``."""
        from adapt.scenario import REALITIES, PluginReality

        r = self.scenario.reality
        if isinstance(r, PluginReality) and r.name in REALITIES:
            return (f"reality kind {r.name!r} ({REALITIES.origin(r.name)}, "
                    f"{r.source.location})")
        return "the reality"

    def _check_size(self) -> None:
        try:
            w, h = (int(v) for v in self.source.size)
        except (TypeError, ValueError):
            raise RunError(f"{self._reality()} gives frames of size {self.source.size!r}; "
                           "expected (width, height)") from None
        cam = self.scenario.camera
        if (w, h) != (cam.width, cam.height):
            raise RunError(f"{self._reality()}'s frames are {w}x{h} but the scenario's camera is "
                           f"{cam.width}x{cam.height} "
                           f"({self.scenario.where('camera.width').location}); "
                           "make them the same size")

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
        """Release the output folder and the agent (the Soar kernel's process); drop the
        trace of a run that never ran.  :meth:`run` calls it when it ends."""
        if self.trace is not None:
            self.trace.abandon()
            self.trace = None
        if self._engine is not None:
            self._engine.close()
            self._engine = None
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    def _trace(self, agent: RuleEngine) -> TraceOutput | None:
        path = self._paths().get("trace")
        if path is None:
            return None
        trace = TraceOutput(path, level=self.outputs.trace_level,
                            files=[str(r.path) for r in self.scenario.rules], seed=self.seed,
                            appearance=self.mirror.appearance, header=agent.trace_header())
        agent.attach_trace(trace.writer)
        self.network.listeners.append(trace.event)
        return trace

    def _open_outputs(self, paths: dict[str, Path]) -> None:
        """The listeners on the frame records, in order: the evaluation (already), the
        report, the trace, the video, the figures' collector, any given."""
        if "report" in paths:
            self.report = ReportOutput(paths["report"], {
                "scenario": str(self.scenario.path) if self.scenario.path else None,
                "seed": self.seed, "fps": self.fps, "reality": self.scenario.reality.name,
                "frames_planned": self.max_frames}, self.evaluation, self.scenario.target)
            self.listeners.append(self.report)
        if self.trace is not None:
            self.listeners.append(self.trace)
        if "video" in paths:
            self.video = VideoOutput(paths["video"], self.fps, self.source.size,
                                     self.outputs.video_codec)
            self.listeners.append(self.video)
        if "figures" in paths:
            self.figures = FigureCollector(fps=self.fps, evaluation=self.evaluation,
                                           target=self.scenario.target,
                                           render_twin=self._render_twin,
                                           twin_radius=self._twin_radius)
            self.listeners.append(self.figures)
        self.listeners.extend(self.extra)

    def _render_twin(self, camera: Camera) -> np.ndarray:
        robot = self.scenario.scene.robot
        also = () if robot is None else tuple(
            b for b in self.mirror.world.snapshot().bodies if b.name == robot.name)
        return self.twin.render(camera, self.mirror.renderer, also=also).image

    def _twin_radius(self, name: str) -> float | None:
        return next((b.radius for b in self.twin.world.balls if b.name == name), None)

    def _on_write(self, text: str) -> None:
        self.stats.write(text)
        if self.on_write is not None:
            self.on_write(text)

    def _on_event(self, event: SchemaEvent) -> None:
        self.stats.event(event)
        self._events.append(event)
        if event.kind is EventKind.CREATED:
            self._created.append(event)

    # -- the loop ------------------------------------------------------------------------------

    def run(self) -> RunResult:
        """Run the loop to the end (or the interrupt); write and return the outputs; release
        the output folder."""
        for _ in self.frames():
            pass
        assert self.result is not None
        return self.result

    def frames(self) -> Generator[FrameRecord, None, None]:
        """The loop one frame at a time: yields each frame's record after its listeners have
        had it (before the imagination steps on).  When the iterator ends -- the run's
        length, a ``(halt)``, Ctrl-C, or the caller closing it early (``break`` then
        ``close()``, or leaving a ``with``; counted as interrupted) -- the outputs are
        written and :attr:`result` holds the :class:`RunResult`.  Between two frames the
        caller may command its own robot or simulator: this is how the loop is closed with
        something outside adapt."""
        try:
            self._open_outputs(self._paths())
            started = time.perf_counter()
            interrupted = False
            error: str | None = None
            try:
                yield from self._loop(started)
            except (KeyboardInterrupt, GeneratorExit):
                interrupted = True
            except BaseException as exc:
                error = f"{type(exc).__name__}: {exc}"
                self.result = self._finish(time.perf_counter() - started, False, error)
                written = self.result.outputs
                if isinstance(exc, EngineError) and written:  # a rule failed, the kernel crashed
                    raise EngineError(
                        f"{exc}; the run stopped in frame {self.frames_done}, and "
                        f"{' and '.join(str(p) for p in written.values())} hold what ran") from exc
                raise
            finally:
                self.source.close()
            self.result = self._finish(time.perf_counter() - started, interrupted, error)
        finally:
            self.close()

    def _loop(self, started: float) -> Iterator[FrameRecord]:
        frames: Iterator[Frame] = iter(self.source)
        while self.frames_done < self.max_frames:
            t0 = time.perf_counter()
            frame = next(frames, None)
            if frame is None:
                break
            self._check_frame(frame)
            self.stats.add("reality", time.perf_counter() - t0)
            record = self._step(frame)
            self.frames_done += 1
            yield record
            if self.agent.halted:
                break
            if self.on_progress is not None:
                wall = time.perf_counter() - started
                self.on_progress(Progress(self.frames_done, self.max_frames, frame.time,
                                          self.frames_done / wall if wall > 0 else 0.0,
                                          len(self.network)))

    def _check_frame(self, frame: object) -> None:
        if not isinstance(frame, Frame) or not isinstance(frame.image, np.ndarray):
            raise RunError(f"{self._reality()} gave {type(frame).__name__}; expected "
                           "adapt.frames.Frame(index, time, image) with a numpy image")
        img = frame.image
        w, h = self.source.size
        if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] != 3 or img.shape[:2] != (h, w):
            raise RunError(f"{self._reality()}: frame {frame.index} is {img.dtype} "
                           f"{tuple(img.shape)}; expected uint8 BGR {h}x{w}x3 like the camera")

    def _step(self, frame: Frame) -> FrameRecord:
        """Steps 2 to 6 of the module docstring for one frame; returns its record."""
        stats = self.stats
        t1 = time.perf_counter()
        self.network.perceive(frame)
        self._create_twins()
        for bg in self.network.published(BackgroundPercept):
            stats.mmd(bg.ms)
        t2 = time.perf_counter()
        self.agent.run(self.scenario.run.decisions_per_frame, footer=False)
        self.network.perceive_spawned()  # a schema spawned this frame looks at it too
        self._create_twins()
        t3 = time.perf_counter()
        self.network.act(frame.time)
        t4 = time.perf_counter()
        record = self._record(frame)  # the imagination as it stands at the frame's time
        for listener in self.listeners:
            listener.frame(record)
        self.network.changed = False
        t5 = time.perf_counter()
        self.mirror.step_to(frame.time + 1.0 / self.fps)
        self.twin.step_to(frame.time + 1.0 / self.fps)
        t6 = time.perf_counter()
        stats.add("perception", t2 - t1)
        stats.add("decisions", t3 - t2)
        stats.add("action", t4 - t3)
        stats.add("physics", t6 - t5)
        stats.add("outputs", t5 - t4)
        return record

    def _create_twins(self) -> None:
        """An object the mirror created this frame is created in the uncorrected twin too,
        with the model's own parameters (or what was measured of an unknown one)."""
        if not self._created:
            return  # most frames (it is called after the perception and after the spawns)
        objects = self.network.published(ObjectPercept)
        for event in self._created:
            name = str(event.data["body"])
            model = next((m for m in self.scenario.objects if m.name == name), None)
            percept = next((p for p in objects if p.object == name), None)
            ball = model.ball if model is not None else None if percept is None else percept.ball
            if ball is not None:
                self.twin.create(ball, event.data["position"], event.data["velocity"])
        self._created.clear()

    def _record(self, frame: Frame) -> FrameRecord:
        objects = tuple(self.network.published(ObjectPercept))
        states = {name: b.step(self.network.time, objects) for name, b in self.baselines.items()}
        pose = self.mirror.robot_pose()
        events, self._events = tuple(self._events), []
        return FrameRecord(
            frame=frame, decisions=self.agent.decisions, schemas=tuple(self.network.names),
            camera=self.mirror.camera,
            background=next(iter(self.network.published(BackgroundPercept)), None),
            objects=objects, tracked=self._tracked(objects),
            robot=None if pose is None else RobotPose(pose[0], pose[1]),
            uncorrected=self.twin.positions(), baselines=states,
            monitored=tuple(self.network.monitored_boxes()), events=events,
            subscene=self.network.subscene() if self.network.changed else None)

    def _tracked(self, objects: tuple[ObjectPercept, ...]) -> tuple[TrackedObject, ...]:
        """Every object of the run: the declared ones, those the schemas follow (observed),
        those in the imagination (imagined)."""
        observed: dict[str, tuple[float, float] | None] = {m.name: None for m in self.scenario.objects}
        for p in objects:
            observed[p.object] = p.observed
        imagined: dict[str, tuple[float, float] | None] = {}
        for ball in self.mirror.scene.balls:
            if self.mirror.has_body(ball.name):
                observed.setdefault(ball.name, None)
                imagined[ball.name] = self.mirror.world.position(ball.name)
        return tuple(TrackedObject(n, o, imagined.get(n)) for n, o in observed.items())

    # -- the end -----------------------------------------------------------------------------------

    def stop(self, interrupted: bool, error: str | None) -> Stop:
        """Why the run stopped."""
        if error is not None:
            return Stop.ERROR
        if interrupted:
            return Stop.INTERRUPTED
        if isinstance(self.source, SourceStatus) and self.source.stalled:
            return Stop.STALLED
        return Stop.HALT if self.agent.halted else Stop.END_OF_FRAMES

    def summary(self, wall: float, interrupted: bool, error: str | None) -> dict[str, Any]:
        """The run's summary (``report.json``'s ``summary``)."""
        out = self.stats.summary(
            frames=self.frames_done, fps=self.fps, wall=wall, interrupted=interrupted,
            error=error, stopped=self.stop(interrupted, error).value,
            decisions=self.agent.decisions, halted=self.agent.halted,
            schemas=self.network.names, schema_s=self.network.seconds,
            objects=self.network.published(ObjectPercept))
        out.update(self.evaluation.summary())
        out["goal_objects"] = self.sightings.summary()
        if isinstance(self.source, SourceStatus):
            out["source"] = self.source.status()
        return out

    def _finish(self, wall: float, interrupted: bool, error: str | None) -> RunResult:
        summary = self.summary(wall, interrupted, error)
        paths = self._paths()
        written: dict[str, Path] = {}
        if self.video is not None:
            path = self.video.close()
            if path is not None:
                written["video"] = path
        if self.trace is not None:
            written["trace"] = self.trace.close(self.agent, summary, wall, error)
            self.trace = None
        if self.report is not None:
            written["report"] = self.report.close(summary)
        bg = next(iter(self.network.published(BackgroundPercept)), None)
        if "appearance" in paths and bg is not None and bg.learn_passes:
            self.mirror.save_appearance(paths["appearance"])
            written["appearance"] = paths["appearance"]
        if self.figures is not None and self.frames_done > 0 and error is None:
            sc = self.scenario
            camera = None if sc.mount.kind is Mount.ROBOT else (
                float(sc.camera.position[0]), float(sc.camera.position[1]))
            data = self.figures.data(sc.scene, camera=camera,
                                     floor_texture=self.mirror.appearance.texture("floor"))
            written.update(write_figures(data, paths["figures"]))
        return RunResult(summary, written, interrupted, error)


def _extras(source: FrameSource) -> tuple[Actuator | None, "GroundTruth | None"]:
    """The source's real robot and ground truth, when it is a reality source (a plain
    frame source has neither)."""
    from adapt.reality import RealitySource

    if isinstance(source, RealitySource):
        return source.robot, source.truth
    return None, None

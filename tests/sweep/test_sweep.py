"""Sweeps on real local Dask clusters: results, resume, failures, dead workers and Ctrl-C."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("distributed")

from adapt.cli import main  # noqa: E402
from adapt.errors import SweepError  # noqa: E402
from adapt.sweep.aggregate import deterministic  # noqa: E402
from adapt.sweep.cluster import connect  # noqa: E402
from adapt.sweep.plan import make_plan  # noqa: E402
from adapt.sweep.session import Progress, run_sweep  # noqa: E402
from adapt.sweep.task import run_task  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
VIDEO = ROOT / "scenarios" / "video-sequence.yaml"


def lines(folder: Path) -> list[dict[str, Any]]:
    return [json.loads(t) for t in (folder / "runs.jsonl").read_text().splitlines()]


def test_a_small_sweep_on_two_worker_processes(room: Path, two_workers: Any,
                                                tmp_path: Path) -> None:
    plan = make_plan(room, seeds="1-3", sets=["reality.appearance.noise=1,3"], max_frames=3)
    seen: list[Progress] = []
    out = run_sweep(plan, tmp_path, client=two_workers.client, on_progress=seen.append)
    assert (out.ok, out.failed, out.lost, out.remaining, out.ran) == (6, 0, 0, 0, 6)
    recs = lines(tmp_path)
    assert sorted(r["key"] for r in recs) == sorted(r.key for r in plan.runs)
    assert len({r["worker"]["pid"] for r in recs}) == 2  # both workers took runs
    assert all(r["metrics"]["frames"] == 3 and r["summary"]["frames"] == 3 for r in recs)
    assert seen[-1].done == 6 and seen[-1].remaining == 0
    doc = json.loads((tmp_path / "sweep.json").read_text())
    assert doc["status"] == "complete" and doc["runs"]["ok"] == 6
    assert [c["set"] for c in doc["cells"]] == [{"reality.appearance.noise": 1},
                                                {"reality.appearance.noise": 3}]
    assert all(c["planned"] == 3 and c["ok"] == 3 for c in doc["cells"])
    cam = doc["overall"]["values"]["camera_rotation_error_deg"]
    assert cam["n"] == 6 and cam["p10"] <= cam["median"] <= cam["p90"]
    assert "Wilson" in doc["intervals"]["rates"]
    assert [v["value"] for v in doc["by_parameter"]["reality.appearance.noise"]] == [1, 3]
    csv_lines = (tmp_path / "runs.csv").read_text().splitlines()
    assert len(csv_lines) == 7 and csv_lines[0].startswith("key,seed,reality.appearance.noise,")
    assert (tmp_path / "figures" / "errors.png").stat().st_size > 10_000
    assert not (tmp_path / "figures" / "rates.png").exists()  # no interception goal: no rates


def test_the_same_seeds_give_the_same_runs_on_one_or_two_workers(room: Path, two_workers: Any,
                                                                tmp_path: Path) -> None:
    plan = make_plan(room, seeds="1-3", sets=["reality.appearance.blur=0.3,1.2"], max_frames=4)
    run_sweep(plan, tmp_path / "two", client=two_workers.client, plots=False)
    with connect(workers=1) as one:
        run_sweep(plan, tmp_path / "one", client=one.client, plots=False)
    two = {r["key"]: deterministic(r) for r in lines(tmp_path / "two")}
    single = {r["key"]: deterministic(r) for r in lines(tmp_path / "one")}
    assert two == single
    # and in this process, without Dask
    spec = plan.runs[4]
    assert deterministic(run_task(spec) or {}) == two[spec.key]
    # the seeds matter: the runs are not all alike
    errors = {r["metrics"]["camera_rotation_error_deg"] for r in two.values()}
    assert len(errors) >= 3


def test_resume_skips_finished_runs(room: Path, two_workers: Any, tmp_path: Path) -> None:
    client = two_workers.client
    first = run_sweep(make_plan(room, seeds="1-2", max_frames=3), tmp_path, client=client,
                      plots=False)
    assert first.ran == 2
    again = run_sweep(make_plan(room, seeds="1-2", max_frames=3), tmp_path, client=client,
                      plots=False)
    assert (again.ran, again.skipped, again.ok) == (0, 2, 2) and again.where == ""
    # a cut-short last line (killed while writing) is dropped and that run runs again
    rec = lines(tmp_path)[-1]
    with (tmp_path / "runs.jsonl").open("a") as f:
        f.write(json.dumps({**rec, "key": "seed3-x"})[:40])
    more = run_sweep(make_plan(room, seeds="1-4", max_frames=3), tmp_path, client=client,
                     plots=False)
    assert (more.ran, more.skipped, more.ok, more.dropped) == (2, 2, 4, 1)
    assert Counter(r["key"] for r in lines(tmp_path)).most_common(1)[0][1] == 1
    # another grid: the runs it shares are skipped, the others stay in runs.jsonl unused
    other = run_sweep(make_plan(room, seeds="3-5", max_frames=3), tmp_path, client=client,
                      plots=False)
    assert (other.ran, other.skipped, other.outside_grid) == (1, 2, 2)
    doc = json.loads((tmp_path / "sweep.json").read_text())
    assert doc["runs"]["ok"] == 3 and doc["runs"]["outside_grid"] == 2
    # another version of the scenario is never mixed in
    with pytest.raises(SweepError, match="another version of the scenario"):
        run_sweep(make_plan(room, seeds="1-2", max_frames=5), tmp_path, client=client)


def test_a_failing_run_is_recorded_and_the_sweep_goes_on(two_workers: Any, tmp_path: Path,
                                                         capsys: pytest.CaptureFixture[str]
                                                         ) -> None:
    # the video's frames are 320 wide: a 640-wide camera makes those runs raise
    status = main(["sweep", str(VIDEO), "--seeds", "1-3", "--set", "camera.width=320,640",
                   "--max-frames", "2", "--scheduler", two_workers.client.scheduler.address,
                   "--out", str(tmp_path), "--quiet"])
    assert status == 9  # Exit.RUNS_FAILED
    recs = lines(tmp_path)
    assert Counter(r["status"] for r in recs) == {"ok": 3, "failed": 3}
    failed = [r for r in recs if r["status"] == "failed"]
    assert all(r["set"] == {"camera.width": 640} for r in failed)
    assert all(r["error"].startswith("RealityError: frame 0") for r in failed)
    assert "Traceback" in failed[0]["traceback"]
    out = capsys.readouterr().out
    assert "3 ok, 3 failed" in out and "3 runs not finished: RealityError" in out
    doc = json.loads((tmp_path / "sweep.json").read_text())
    assert doc["errors"][0]["runs"] == 3
    assert [c["failed"] for c in doc["cells"]] == [0, 3]
    # resuming (the same command) leaves failed runs alone unless asked
    assert main(["sweep", str(VIDEO), "--seeds", "1-3", "--set", "camera.width=320,640",
                 "--max-frames", "2", "--out", str(tmp_path), "--json"]) == 9  # no cluster
    done = json.loads(capsys.readouterr().out)
    assert done["runs"]["ran_now"] == 0 and done["runs"]["failed"] == 3
    assert done["outputs"]["sweep"] == str(tmp_path / "sweep.json")
    plan = make_plan(VIDEO, seeds="1-3", sets=["camera.width=320,640"], max_frames=2)
    retried = run_sweep(plan, tmp_path, client=two_workers.client, plots=False,
                        retry_failed=True)
    assert (retried.ran, retried.failed) == (3, 3)


def test_a_killed_worker_loses_no_run_and_counts_none_twice(room: Path, two_workers: Any,
                                                            tmp_path: Path) -> None:
    client = two_workers.client
    plan = make_plan(room, seeds="1-8", max_frames=16)
    killed: dict[str, Any] = {}

    def kill_one(p: Progress) -> None:
        if killed or p.done < 1:
            return
        busy = {w: ks for w, ks in client.processing().items() if ks}
        if not busy:
            return
        worker = next(iter(busy))
        pid = client.run(os.getpid, workers=[worker])[worker]
        os.kill(pid, signal.SIGKILL)
        killed.update(pid=pid)

    out = run_sweep(plan, tmp_path, client=client, on_progress=kill_one, plots=False)
    assert killed, "no worker was busy to kill"
    recs = lines(tmp_path)
    keys = Counter(r["key"] for r in recs)
    assert set(keys) == {r.key for r in plan.runs} and max(keys.values()) == 1
    assert all(r["status"] == "ok" for r in recs)
    assert (out.ok, out.remaining, out.lost) == (8, 0, 0) and out.workers_left >= 1
    # (a run the dead worker held was run again by a live one, unless it finished just before
    # the kill: which of the two happened is a race, so it is not asserted)
    client.wait_for_workers(2, timeout=60)  # the nanny restarts it for the next tests


def test_ctrl_c_writes_the_aggregate_of_the_runs_done(room: Path, two_workers: Any,
                                                      tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    cmd = [sys.executable, "-m", "adapt", "sweep", str(room), "--seeds", "1-24",
           "--max-frames", "3", "--workers", "2", "--out", str(out), "--no-plots"]
    proc = subprocess.Popen(cmd, cwd=ROOT, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 90
        while time.monotonic() < deadline and proc.poll() is None:
            runs = out / "runs.jsonl"
            if runs.exists() and runs.read_text().count("\n") >= 2:
                break
            time.sleep(0.05)
        assert proc.poll() is None, proc.communicate()
        os.killpg(proc.pid, signal.SIGINT)  # as a terminal does: the client and its workers
        stdout, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130, stderr
    assert "interrupted:" in stdout
    recs = lines(out)
    doc = json.loads((out / "sweep.json").read_text())
    assert doc["status"] == "interrupted"
    assert doc["runs"]["ok"] == len(recs) == len({r["key"] for r in recs}) >= 2
    assert doc["runs"]["remaining"] == 24 - len(recs) > 0
    assert all(r["status"] == "ok" for r in recs)  # no run was cut short and kept
    for _ in range(100):  # the embedded cluster's processes are gone with it
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail("worker processes outlived the interrupted sweep")
    # the same command goes on from there
    plan = make_plan(room, seeds="1-24", max_frames=3)
    rest = run_sweep(plan, out, client=two_workers.client, plots=False)
    assert (rest.skipped, rest.ok, rest.remaining) == (len(recs), 24, 0)
    assert max(Counter(r["key"] for r in lines(out)).values()) == 1


def test_bad_arguments_fail_before_anything_runs(room: Path, tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "never"
    assert main(["sweep", str(room), "--seeds", "1-3,x", "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert "--seeds:1:5: expected a seed" in err and "    1-3,x\n        ^" in err
    assert main(["sweep", str(room), "--set", "reality.appearance.noise=1,-2",
                 "--out", str(out)]) == 1
    assert "--set:1:28: reality.appearance.noise" in capsys.readouterr().err
    assert not out.exists()


def test_without_dask_the_command_says_how_to_install_it(room: Path, tmp_path: Path,
                                                         monkeypatch: pytest.MonkeyPatch,
                                                         capsys: pytest.CaptureFixture[str]
                                                         ) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)
    assert main(["sweep", str(room), "--out", str(tmp_path / "x")]) == 1
    assert "pip install 'adapt[sweep]'" in capsys.readouterr().err


def test_kept_outputs_go_into_a_folder_per_run(room: Path, two_workers: Any,
                                               tmp_path: Path) -> None:
    plan = make_plan(room, seeds="1-2", sets=["outputs.video=false", "outputs.figures=false"],
                     max_frames=2, out=tmp_path, keep_outputs=True)
    run_sweep(plan, tmp_path, client=two_workers.client, plots=False)
    for rec in lines(tmp_path):
        folder = tmp_path / "runs" / rec["key"]
        assert rec["outputs"] == str(folder)
        report = json.loads((folder / "report.json").read_text())
        assert report["seed"] == rec["seed"] and report["summary"]["frames"] == 2
        assert (folder / "trace.jsonl").exists() and not (folder / "mmd.mp4").exists()

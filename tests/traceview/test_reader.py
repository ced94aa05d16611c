from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

from adapt.errors import TraceError
from adapt.traceview.reader import Trace, TraceWarning, cycle_of


def test_header_is_read(counter_trace) -> None:
    trace = Trace(counter_trace(3, level=4, seed=7))
    assert (trace.header.level, trace.header.seed, trace.header.files) == (
        4, 7, ("rules/counter.soar",))


def test_records_stream_in_order_and_end_with_the_footer(counter_trace) -> None:
    records = list(Trace(counter_trace(5)).records())
    assert records[-1]["kind"] == "footer"
    ds = [r["d"] for r in records[:-1]]
    assert ds == sorted(ds)
    assert sum(r["kind"] == "decision" for r in records) == 5


def test_cycles_group_input_and_proposal_with_the_next_decision(counter_trace) -> None:
    cycles = dict(Trace(counter_trace(4)).cycles())
    assert sorted(cycles) == [1, 2, 3, 4]
    kinds = [(r["kind"], r.get("phase"), r["d"]) for r in cycles[2]]
    assert kinds == [("phase", "input", 1), ("phase", "proposal", 1), ("phase", "decision", 2),
                     ("decision", None, 2), ("phase", "apply", 2), ("phase", "output", 2)]


def test_cycles_stop_after_the_last_one_asked(counter_trace) -> None:
    got = [c for c, _ in Trace(counter_trace(30)).cycles(first=5, last=7)]
    assert got == [5, 6, 7]


def test_cycle_of_header_and_footer_is_none() -> None:
    assert cycle_of({"kind": "header"}) is None and cycle_of({"kind": "footer"}) is None


def test_truncated_last_line_is_skipped_with_a_warning(counter_trace) -> None:
    whole = list(Trace(counter_trace(10, footer=False)).records())
    path = counter_trace(10, footer=False, truncate=True)
    trace = Trace(path)
    with pytest.warns(TraceWarning, match=r"the last line is truncated .*read the \d+ complete"):
        cut = list(trace.records())
    assert cut == whole[:-1]
    assert trace.notices and "truncated" in trace.notices[0]
    assert trace.footer() is None


def test_a_bad_line_in_the_middle_is_an_error(counter_trace) -> None:
    path = counter_trace(5)
    lines = path.read_text().splitlines(keepends=True)
    lines[3] = "{not json\n"
    path.write_text("".join(lines))
    with pytest.raises(TraceError, match=r":4: not a JSON record"):
        list(Trace(path).records())


@pytest.mark.parametrize("text", [
    "", "hello world\n", "sp {x (state <s>) --> (write hi)}\n",
    json.dumps({"kind": "decision", "d": 1}) + "\n",
    json.dumps({"kind": "header", "format": "soar-trace", "version": 1}) + "\n",
])
def test_not_a_trace(tmp_path: Path, text: str) -> None:
    path = tmp_path / "x.jsonl"
    path.write_text(text)
    with pytest.raises(TraceError, match="not an adapt trace|empty file"):
        Trace(path)


def test_binary_file_is_not_a_trace(tmp_path: Path) -> None:
    path = tmp_path / "x.png"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff\xfe")
    with pytest.raises(TraceError, match="not an adapt trace"):
        Trace(path)


def test_other_version_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "v2.jsonl"
    path.write_text(json.dumps({"kind": "header", "format": "adapt-trace", "version": 2}) + "\n")
    with pytest.raises(TraceError, match="format version 2; this adapt reads version 1"):
        Trace(path)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(TraceError, match="no such trace file"):
        Trace(tmp_path / "nope.jsonl")


def test_no_warning_for_a_complete_trace(counter_trace) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sum(1 for _ in Trace(counter_trace(5)).records()) > 5


# -- issue 21: bounded work on any file, and one trace per file ---------------------------------

@pytest.mark.parametrize("command", [["trace", "stats"], ["trace", "html"], ["trace", "show"]])
def test_a_device_is_refused_at_once(command: list[str], tmp_path: Path, capsys) -> None:
    """``adapt trace stats /dev/zero`` used to run past 60 s and grow to 12 GB."""
    import time

    from adapt.cli import main

    started = time.monotonic()
    argv = [*command, "/dev/zero"] + (["--out", str(tmp_path / "p.html")]
                                      if command[1] == "html" else [])
    assert main(argv) == 1
    assert time.monotonic() - started < 5
    err = capsys.readouterr().err
    assert err.startswith("adapt: error: /dev/zero: not a regular file"), err


def test_a_huge_line_is_refused_in_bounded_memory(counter_trace, tmp_path: Path, capsys) -> None:
    """A 400 MB line used 812 MB before it was refused."""
    import tracemalloc

    from adapt.cli import main

    path = tmp_path / "huge.jsonl"
    head = Path(counter_trace(2)).read_text().splitlines(keepends=True)[0]
    with open(path, "wb") as f:
        f.write(head.encode())
        f.seek(len(head) + 400 * 1024 * 1024)  # a hole: 400 MB of zeros, no disk used
        f.write(b"\n")
    tracemalloc.start()
    try:
        status = main(["trace", "stats", str(path)])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 100 * 1024 * 1024, f"{peak / 2**20:.0f} MiB"
    assert status == 1
    assert "huge.jsonl:2: the line is longer than 32 MiB" in capsys.readouterr().err


def test_two_traces_one_after_the_other_are_refused(counter_trace, tmp_path: Path) -> None:
    one = Path(counter_trace(3)).read_text()
    path = tmp_path / "two.jsonl"
    path.write_text(one + one)
    with pytest.raises(TraceError, match=r"two\.jsonl:(\d+): a second header record: this file "
                       "holds two traces one after the other"):
        list(Trace(path).records())

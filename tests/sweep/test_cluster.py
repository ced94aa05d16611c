"""Where a sweep runs: the embedded cluster's size, and a scheduler address that is not one
(issue 21: a service that speaks first was an internal error, an HTTP server took 59 s)."""

from __future__ import annotations

import http.server
import socket
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from adapt.cli import main
from adapt.errors import SweepError

pytest.importorskip("distributed")

from adapt.sweep.cluster import connect, default_workers  # noqa: E402


def _serve(handle) -> Iterator[str]:  # type: ignore[no-untyped-def]
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    stop = threading.Event()

    def loop() -> None:
        server.settimeout(0.1)
        held = []
        while not stop.is_set():
            try:
                conn, _ = server.accept()
            except OSError:
                continue
            handle(conn)
            held.append(conn)  # kept open: the client must not wait for the end
        for conn in held:
            conn.close()

    thread = threading.Thread(target=loop, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:
        stop.set()
        thread.join()
        server.close()


@pytest.fixture()
def ssh() -> Iterator[str]:
    """A service that speaks first, as an SSH server does."""
    yield from _serve(lambda conn: conn.sendall(b"SSH-2.0-OpenSSH_9.6p1 Ubuntu-3ubuntu13\r\n"))


@pytest.fixture()
def silent() -> Iterator[str]:
    """A service that waits for the client to speak first, as an HTTP server does."""
    yield from _serve(lambda conn: None)


@pytest.fixture()
def web() -> Iterator[str]:
    server = http.server.HTTPServer(("127.0.0.1", 0), http.server.SimpleHTTPRequestHandler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


@pytest.mark.parametrize("service", ["ssh", "silent", "web"])
def test_a_scheduler_address_that_is_not_dask_is_refused_within_seconds(
        service: str, request: pytest.FixtureRequest) -> None:
    address = request.getfixturevalue(service)
    started = time.monotonic()
    with pytest.raises(SweepError, match="is not a Dask scheduler") as info:
        with connect(scheduler=address):
            pass
    assert time.monotonic() - started < 10
    if service == "ssh":
        assert "SSH-2.0" in str(info.value)


def test_the_command_says_so(ssh: str, room: Path, tmp_path: Path, capsys) -> None:
    status = main(["sweep", str(room), "--seeds", "1", "--scheduler", ssh, "--out",
                   str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 1 and "is not a Dask scheduler" in err and "internal error" not in err, err


def test_more_workers_than_cores_are_refused_at_once(room: Path, tmp_path: Path, capsys) -> None:
    cores = default_workers()
    started = time.monotonic()
    with pytest.raises(SweepError, match=f"--workers {cores + 62}: .* {cores} core"):
        with connect(workers=cores + 62):
            pass
    assert time.monotonic() - started < 2
    assert main(["sweep", str(room), "--seeds", "1", "--workers", "64", "--out",
                 str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert f"use --workers 1..{cores}" in err and "Traceback" not in err, err

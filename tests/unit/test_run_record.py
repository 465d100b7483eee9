"""Whether a run recorded in an output folder's marker still lasts: by process id and start
time on this host, by heartbeat for a run of another host (shared storage)."""

from __future__ import annotations

import datetime as dt
import json
import os
import socket
import time

import pytest

from radscene.errors import ConfigError
from radscene.io import run_record
from radscene.io.run_record import (
    MARKER,
    STALE_AFTER,
    RunRecord,
    _process_started,
    _sha256,
    finished,
)


def _stopped_folder(tmp_path, **run):
    """An output folder whose marker holds one run of scene s.yaml that finished observer a."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    scene = tmp_path / "s.yaml"
    scene.write_text("name: s\n")
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.nc").write_text("data")
    now = dt.datetime.now(dt.UTC)
    entry = {"scene": str(scene), "scene_sha256": _sha256(scene), "observers": ["a", "b"],
             "finished": ["a"], "files": {"a": ["a.nc"]},
             "started": (now - dt.timedelta(hours=2)).isoformat(timespec="seconds"), **run}
    (out / MARKER).write_text(json.dumps({"runs": {"x": entry}, "completed": {}}))
    return out, scene


def _change(out, **run):
    marker = json.loads((out / MARKER).read_text())
    marker["runs"]["x"].update(run)
    (out / MARKER).write_text(json.dumps(marker))


def _ago(seconds):
    return (dt.datetime.now(dt.UTC) - dt.timedelta(seconds=seconds)).isoformat(timespec="seconds")


def test_a_run_of_another_host_lasts_until_its_heartbeat_is_stale(tmp_path):
    out, scene = _stopped_folder(tmp_path, host="elsewhere.example", pid=1,
                                 heartbeat=_ago(60))
    with pytest.raises(ConfigError, match=r"--resume: a run still writes into .* \(process 1 on "
                                          r"elsewhere\.example, last heard from at .*\); a run of "
                                          r"another host counts as stopped 10 min after .* remove"):
        finished(out, scene)
    _change(out, heartbeat=_ago(STALE_AFTER + 60))  # it crashed 11 min ago: --resume takes over
    assert finished(out, scene) == ["a"]


def test_a_process_id_reused_by_another_program_is_a_stopped_run(tmp_path):
    """This test's own process is alive, but it is not the run if it started at another time."""
    me = socket.gethostname()
    if _process_started(os.getpid()) is None:
        pytest.skip("no /proc: the start time of a process is not known here")
    out, scene = _stopped_folder(tmp_path, host=me, pid=os.getpid(), pid_started="1")
    assert finished(out, scene) == ["a"]
    out, scene = _stopped_folder(tmp_path / "again", host=me, pid=os.getpid(),
                                 pid_started=_process_started(os.getpid()))
    with pytest.raises(ConfigError, match=f"a run still writes into .*process {os.getpid()} on {me}"):
        finished(out, scene)


def test_the_heartbeat_is_rewritten_while_a_run_lasts(tmp_path, monkeypatch):
    clock = iter(dt.datetime(2026, 1, 1, tzinfo=dt.UTC) + dt.timedelta(minutes=k)
                 for k in range(10_000))
    monkeypatch.setattr(run_record, "_now", lambda: next(clock))
    monkeypatch.setattr(run_record, "HEARTBEAT", 0.05)
    scene = tmp_path / "s.yaml"
    scene.write_text("name: s\n")
    out = tmp_path / "out"

    def beat():
        return next(iter(json.loads((out / MARKER).read_text())["runs"].values()))["heartbeat"]

    with RunRecord(out, scene, ["a"]):
        first = beat()
        deadline = time.monotonic() + 10
        while beat() == first and time.monotonic() < deadline:
            time.sleep(0.05)
        assert beat() > first
        record = next(iter(json.loads((out / MARKER).read_text())["runs"].values()))
        assert record["host"] == socket.gethostname() and record["pid"] == os.getpid()
    assert not (out / MARKER).exists()  # a clean end: the manifest replaces it

"""A SIGTERM whose exception Python drops (it arrived inside a callback called from C) is not
lost: the stop is recorded and raised again at the next check."""

from __future__ import annotations

import ctypes
import os
import signal
import sys

import pytest

from radscene.io import stop


@pytest.fixture
def handlers():
    previous = stop.install()
    yield
    stop.restore(previous)
    stop.reset()


def _signal_inside_a_c_callback(number):
    """Send ``number`` to this process from within a ctypes callback, where the exception its
    handler raises is printed as "Exception ignored" and dropped."""
    def callback():
        os.kill(os.getpid(), number)
        for _ in range(1000):  # bytecodes for the handler to run between
            pass

    ctypes.CFUNCTYPE(None)(callback)()


@pytest.mark.parametrize("number", [signal.SIGTERM, signal.SIGINT])
def test_a_dropped_stop_is_raised_at_the_next_check(handlers, number, monkeypatch):
    dropped = []
    monkeypatch.setattr(sys, "unraisablehook", lambda raised: dropped.append(raised.exc_type))
    stop.check()  # nothing asked yet
    _signal_inside_a_c_callback(number)  # returns: the exception was dropped
    assert dropped == [KeyboardInterrupt]
    assert stop.requested() == number
    with pytest.raises(KeyboardInterrupt, match=f"signal {int(number)}"):
        stop.check()
    with pytest.raises(KeyboardInterrupt):  # again, until it is taken
        stop.check()
    stop.reset()
    stop.check()


def test_the_handler_raises_at_once_where_it_can(handlers):
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):
            pass
    assert stop.requested() == signal.SIGTERM


def test_install_and_restore_put_back_the_handlers():
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    previous = stop.install()
    assert stop.install() == {}  # installed once
    stop.restore(previous)
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before

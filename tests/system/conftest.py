"""Helpers shared by the system tests: small scenes built as dicts."""

from __future__ import annotations

import pytest


def plate_scene(material: dict, atmosphere: dict, bands: list[dict], sun_zenith: float = 30.0,
                sun_azimuth: float = 180.0, temperature: str = "300 K", **render):
    """A 200 m square horizontal plate seen from nadir over its centre."""
    return {
        "name": "plate",
        "environment": {"sun": {"zenith": sun_zenith, "azimuth": sun_azimuth},
                        "atmosphere": atmosphere},
        "materials": {"plate_material": material},
        "objects": [{"name": "plate", "shape": {"type": "plate", "width": 200, "length": 200},
                     "position": [0, 0, 0], "material": "plate_material",
                     "temperature": temperature}],
        "bands": bands,
        "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                       "shape": [8, 8], "altitude": 1000}],
        "render": render or {},
    }


@pytest.fixture
def make_plate_scene():
    return plate_scene


def _one_line_refusal(output: str, *words: str) -> str:
    """Check a refusal on the command line: one line, 'error: KEY: ...', holding ``words``, no
    traceback; returns the line."""
    lines = [line for line in output.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: "), output
    assert "Traceback" not in output
    for word in words:
        assert word in lines[0], output
    return lines[0]


@pytest.fixture
def one_line_refusal():
    """:func:`_one_line_refusal`, for tests of bad input at the command line."""
    return _one_line_refusal

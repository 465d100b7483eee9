"""What the command line shows writes micrometres as µm: help texts, printed lines, tables,
plot labels and quicklook labels (``um`` stays what a user may type and what files carry)."""

from __future__ import annotations

import re
import textwrap

import matplotlib.figure
import matplotlib.text
import pytest
import typer
from typer.testing import CliRunner

from radscene import example_path
from radscene.cli import app

runner = CliRunner()

#: ``um`` as a unit: after a space or a bracket, not part of a word; "(um, nm)" lists the
#: spellings an option takes, "[default: um]" is one of them, "12um" is what a user types
UM = re.compile(r"(?<!default:)[ \[]um(?![A-Za-z_])")

SCENE = textwrap.dedent("""
    name: tiny
    environment:
      sun: {zenith: 30 deg, azimuth: 180 deg}
      atmosphere: {type: none}
    materials:
      paint: {reflectance: 0.4}
    objects:
      - {name: plate, shape: {type: plate, width: 50 m, length: 50 m}, material: paint,
         temperature: 300 K}
    bands:
      - {name: vis, min: 0.5 um, max: 0.6 um}
      - {name: lwir, min: 8 um, max: 12 um}
    observers:
      - {name: nadir, type: orthographic, center: [0, 0], gsd: 1 m, shape: [4, 4]}
      - {name: spectro, type: orthographic, center: [0, 0], gsd: 1 m, shape: [2, 2],
         spectral: {min: 0.5 um, max: 0.6 um, step: 0.05 um}}
""")


def _no_um(text: str, what: str) -> None:
    flat = " ".join(text.split())
    found = [flat[max(0, m.start() - 40):m.end() + 10] for m in UM.finditer(flat)]
    assert not found, f"{what} writes 'um': {found}"


@pytest.fixture
def figure_texts(monkeypatch):
    """Every text of every figure saved while the test runs."""
    texts = []
    save = matplotlib.figure.Figure.savefig

    def recording(self, *args, **kwargs):
        texts.extend(t.get_text() for t in self.findobj(matplotlib.text.Text))
        return save(self, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", recording)
    return texts


def _commands(group, path=()):
    for name, command in group.commands.items():
        yield (*path, name)
        if getattr(command, "commands", None):
            yield from _commands(command, (*path, name))


def test_help_texts_say_micrometres():
    top = typer.main.get_command(app)
    paths = list(_commands(top))
    assert ("atmosphere", "los") in paths and ("materials", "plot") in paths
    for path in [(), *paths]:
        result = runner.invoke(app, [*path, "--help"], env={"COLUMNS": "250"})
        assert result.exit_code == 0, (path, result.output)
        _no_um(result.output, "radscene " + " ".join(path) + " --help")


def test_printed_lines_and_tables_say_micrometres(tmp_path):
    result = runner.invoke(app, ["examples"], env={"COLUMNS": "250"})
    # the table's cells wrap with the console's width (fixed once per process): µm, wrapped or not
    assert result.exit_code == 0 and "µm" in result.output, result.output
    _no_um(result.output, "radscene examples")
    result = runner.invoke(app, ["check", str(example_path("hyperspectral"))],
                           env={"COLUMNS": "250"})
    assert result.exit_code == 0, result.output
    assert "211 channels 0.4–2.5 µm every 0.01 µm" in " ".join(result.output.split())
    _no_um(result.output, "radscene check")
    for command in (["materials", "list"], ["materials", "show", "asphalt"]):
        result = runner.invoke(app, command, env={"COLUMNS": "250"})
        assert result.exit_code == 0, result.output
        _no_um(result.output, "radscene " + " ".join(command))


def test_plot_labels_say_micrometres(tmp_path, figure_texts):
    result = runner.invoke(app, ["materials", "plot", "asphalt", "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    result = runner.invoke(app, ["atmosphere", "los", "--wavelength-min", "0.45",
                                 "--wavelength-max", "0.9", "--band", "0.63,0.69",
                                 "--plot", str(tmp_path / "los.png")], env={"COLUMNS": "250"})
    assert result.exit_code == 0, result.output
    _no_um(result.output, "radscene atmosphere los")
    result = runner.invoke(app, ["atmosphere", "sky", "--zenith", "0,60", "--azimuth", "0,180",
                                 "--wavelength-min", "0.4", "--wavelength-max", "1.0",
                                 "--plot", str(tmp_path / "sky.png")], env={"COLUMNS": "250"})
    assert result.exit_code == 0, result.output
    _no_um(result.output, "radscene atmosphere sky")
    assert any("wavelength [µm]" in t for t in figure_texts), figure_texts
    _no_um("\n".join(figure_texts), "a plot")


def test_render_output_and_quicklooks_say_micrometres(tmp_path, figure_texts):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE)
    result = runner.invoke(app, ["render", str(scene), "-o", str(tmp_path / "out")],
                           env={"COLUMNS": "250"})
    assert result.exit_code == 0, result.output
    _no_um(result.output, "radscene render")
    assert figure_texts
    _no_um("\n".join(figure_texts), "a quicklook")

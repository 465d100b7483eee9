"""The API reference's conversion of the docstrings' reStructuredText to Markdown
(``scripts/griffe_rst.py``): every docstring of the package loses its roles, math directives,
simple tables, double-backquoted literals and ``::`` blocks, and the real ones come out as the
Markdown tables, equations and cross-references they mean."""

from __future__ import annotations

import ast
import importlib.util
import re
from pathlib import Path

import pytest

griffe = pytest.importorskip("griffe", reason="the API reference needs griffe (the docs extra)")

ROOT = Path(__file__).resolve().parents[2]
ROLE = re.compile(r":(?:py:)?[a-z]+:`")
RULE = re.compile(r"^\s*=+( +=+)+\s*$", re.M)


def _module():
    spec = importlib.util.spec_from_file_location("griffe_rst", ROOT / "scripts" / "griffe_rst.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def rst():
    return _module()


@pytest.fixture(scope="module")
def package(rst):
    return griffe.load("radscene", search_paths=[str(ROOT / "src")], docstring_parser="numpy",
                       extensions=griffe.load_extensions(rst.RstToMarkdown))


def _objects(obj):
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _objects(member)


def _prose(text: str) -> str:
    """``text`` without its fenced code blocks, equations and doctest paragraphs."""
    text = re.sub(r"^\s*```.*?^\s*```", "", text, flags=re.M | re.S)
    text = re.sub(r"^\s*\$\$.*?^\s*\$\$", "", text, flags=re.M | re.S)
    return "\n\n".join(p for p in re.split(r"\n\s*\n", text) if not p.lstrip().startswith(">>>"))


def _source_math_directives() -> int:
    count = 0
    for path in (ROOT / "src" / "radscene").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef):
                doc = ast.get_docstring(node) or ""
                count += len(re.findall(r"^\s*\.\. math::", doc, re.M))
    return count


def test_no_docstring_keeps_restructuredtext(package):
    leftovers = []
    for obj in _objects(package):
        if obj.docstring is None:
            continue
        prose = _prose(obj.docstring.value)
        for what, pattern in (("role", ROLE), ("math directive", re.compile(r"\.\. math::")),
                              ("table rule", RULE), ("literal", re.compile(r"(?<!`)``(?!`)")),
                              ("literal block", re.compile(r"::\s*$", re.M))):
            if pattern.search(prose):
                leftovers.append(f"{obj.path}: {what}")
    assert not leftovers, "\n".join(leftovers)


def test_every_math_directive_becomes_display_math(package):
    blocks = sum(len(re.findall(r"^\s*\$\$\s*$", obj.docstring.value, re.M)) // 2
                 for obj in _objects(package) if obj.docstring is not None)
    directives = _source_math_directives()
    assert directives > 100
    assert blocks >= directives  # an equation per directive, more where one holds several


def test_a_parameter_table_and_a_literal_block(package):
    doc = package["atmosphere.uniform"].docstring.value
    assert "| name | unit | default | meaning |\n| --- | --- | --- | --- |" in doc
    assert "| `transmittance` | - | 1 | τ_a, target to observer |" in doc
    assert "| `sky_profile` | - | (none) | multiplier of `sky_radiance` there |" in doc
    assert "Example:\n\n```\natmosphere:\n  type: uniform\n" in doc


def test_continuation_lines_join_their_row_and_roles_in_cells_resolve(package):
    doc = package["atmosphere.bands"].docstring.value
    row = next(line for line in doc.splitlines() if line.startswith("| `band_<r>_brightness"))
    assert "the temperature of the blackbody with the same ∫ S L dλ" in row
    assert ('<autoref identifier="radscene.atmosphere.bands.THERMAL_BAND_MIN" optional>'
            "`THERMAL_BAND_MIN`</autoref>") in row
    assert row.count(" | ") == 2  # three cells


def test_equations_one_block_each(package):
    doc = package["sensor.analysis.performance"].docstring.value
    blocks = re.findall(r"^\$\$\n(.*?)\n\$\$$", doc, re.M | re.S)
    assert len(blocks) == 2
    assert blocks[0].startswith(r"s = \frac{t}{q} G \int S \tau R L\, d\lambda")
    assert blocks[1].endswith(r"\mathrm{SNR} = s / \sigma_{temporal}")
    # inside a numpydoc Returns item: no blank line between the type and its description
    returns = package["sensor.detector.dark_current"].docstring.value
    assert "numpy.ndarray\n    $$\n    I_d(T) = " in returns


def test_inline_math_spanning_lines(package):
    doc = package["materials.brdf.coxmunk"].docstring.value
    assert r"$p(z_x, z_y) = \exp(-\tan^2\theta_h/\sigma^2) /(\pi\sigma^2)$" in doc


def test_roles_resolve_in_scope_to_canonical_paths(package):
    doc = package["pipeline.render"].docstring.value
    assert ('<autoref identifier="radscene.pipeline.render_hyperspectral" optional>'
            "`render_hyperspectral`</autoref>") in doc
    # a tilde keeps the last name; a module outside the pages still gets its identifier
    bands = package["atmosphere.bands"].docstring.value
    assert ('<autoref identifier="radscene.radiometry.srf.SpectralResponse.integrate" '
            'optional>`integrate`</autoref>') in bands


def test_unresolved_names_are_plain_code(rst):
    text = "See :func:`numpy.interp` and :class:`Nowhere`, :ref:`a-label`."
    assert rst.rst_to_markdown(text) == "See `numpy.interp` and `Nowhere`, `a-label`."


def test_brackets_are_not_reference_links(package, rst):
    doc = package["sensor.detector.PhotonDetector.clip"].docstring.value
    assert r"[0, full_well] \[e-]" in doc
    # but not in code, math or doctests
    text = "``a[0] [1]`` and :math:`[a] [b]`\n\n>>> x[0] [1]"
    assert rst.rst_to_markdown(text) == "`a[0] [1]` and $[a] [b]$\n\n>>> x[0] [1]"
    # a doctest's output either, where the section heading runs into the doctest
    text = "Examples\n--------\n>>> f([[1, 2]])[:1]]\n[0.5, 3.5]"
    assert rst.rst_to_markdown(text) == text
    project = package["platform.cameras.OrthographicCamera.project"].docstring.value
    assert "]\n[0.5, 3.5]" in project and "\\[" not in project


def test_table_without_header_and_pipes_escaped(rst):
    text = "\n".join(["Intro.", "", "=====  =========", "a|b    :math:`|x|`", "c      ``d|e``",
                      "=====  =========", "", "After."])
    assert rst.rst_to_markdown(text) == "\n".join([
        "Intro.", "", "|  |  |", "| --- | --- |", r"| a\|b | $\vert x\vert $ |",
        "| c | `d|e` |", "", "After."])

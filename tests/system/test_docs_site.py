"""The documentation site builds in strict mode, and its API reference shows the docstrings'
reStructuredText as what it means: equations as MathML made when the site is built (no script,
no network, no raw TeX left), tables as tables, roles as links, no raw markup left."""

from __future__ import annotations

import html as htmllib
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mkdocstrings_handlers.python", reason="the site needs the docs extra")
pytest.importorskip("pymdownx.arithmatex", reason="the site needs the docs extra")
pytest.importorskip("latex2mathml", reason="the site needs the docs extra")

ROOT = Path(__file__).resolve().parents[2]
RAW = re.compile(r":(?:func|class|mod|meth|data|attr|math|obj|exc):`?<code>|:(?:func|class|mod|"
                 r"meth|data|attr|math):`|\.\. math::|^\s*(?:<p>)?=+(?: +=+)+|::</p>", re.M)
#: TeX in a page's text: math delimiters, or a command (a backslash and letters).
TEX = re.compile(r"\\[([]|\$\$|\\[A-Za-z]+")
#: Where a backslash may stand: code, scripts, styles and MathML.
VERBATIM = re.compile(r"<(code|pre|script|style|math)\b.*?</\1>", re.S)
#: A script from another host.
REMOTE_SCRIPT = re.compile(r"<script\b[^>]*\bsrc=\"(?:https?:)?//", re.I)


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1",
           "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
                          str(out)], cwd=ROOT, env=env, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "WARNING" not in run.stderr, run.stderr[-3000:]
    return out


def _page(site: Path, name: str) -> str:
    return (site / "api" / name / "index.html").read_text(encoding="utf-8")


def test_no_raw_restructuredtext_on_any_api_page(site):
    pages = sorted((site / "api").glob("*/index.html"))
    assert len(pages) >= 11
    for page in pages:
        html = page.read_text(encoding="utf-8")
        found = RAW.findall(html)
        assert not found, f"{page.parent.name}: {found[:5]}"


def _raw_tex(html: str) -> list[str]:
    """The TeX in the text of a page (outside code, scripts, styles and MathML), in context."""
    text = htmllib.unescape(re.sub(r"<[^>]*>", " ", VERBATIM.sub(" ", html)))
    return [" ".join(text[max(m.start() - 30, 0):m.end() + 30].split())
            for m in TEX.finditer(text)]


def test_no_page_loads_math_from_the_network_or_shows_raw_tex(site):
    pages = sorted(site.rglob("*.html"))
    assert len(pages) >= 25
    equations = 0
    for page in pages:
        html = page.read_text(encoding="utf-8")
        name = str(page.relative_to(site))
        assert not REMOTE_SCRIPT.search(html), f"{name}: a script from another host"
        assert not re.search(r"<script\b[^>]*mathjax", html, re.I), name
        assert "arithmatex" not in html, f"{name}: an equation left unconverted"
        assert not _raw_tex(html), f"{name}: {_raw_tex(html)[:5]}"
        equations += html.count("<math ")
    assert equations >= 140  # every equation of the docstrings
    assert not (site / "javascripts" / "mathjax.js").exists()


def test_no_page_loads_anything_from_another_host(site):
    """Scripts, style sheets and web fonts alike: the site reads offline."""
    for page in sorted(site.rglob("*.html")):
        html = page.read_text(encoding="utf-8")
        remote = re.findall(r"<(?:link|script)\b[^>]*(?:href|src)=\"(?:https?:)?//[^\"]+", html)
        assert not remote, f"{page.relative_to(site)}: {remote[:3]}"


def _mathml(html: str) -> str:
    """A page's HTML with its tags' attributes dropped and its entities resolved."""
    return htmllib.unescape(re.sub(r"<(/?[a-z]+)\b[^>]*?(/?)>", r"<\1\2>", html))


def test_equations_are_mathml(site):
    atmosphere = _page(site, "atmosphere")
    # $$ L = L_{path} + ... $$: a display equation, its subscript a MathML script
    assert re.search(r'<math xmlns="http://www\.w3\.org/1998/Math/MathML" display="block">'
                     r"\s*<mrow>\s*<mi>L</mi>\s*<mo>&#x0003D;</mo>\s*<msub>\s*<mi>L</mi>",
                     atmosphere)
    assert "<mi>p</mi><mi>a</mi><mi>t</mi><mi>h</mi>" in atmosphere
    brdf = _page(site, "brdf_models")
    assert brdf.count('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">') >= 20
    assert brdf.count('display="inline"') >= 10
    # the Planck law: L = c_1L / lambda^5 * 1 / (e^(c_2 / lambda T) - 1)
    radiometry = _mathml(_page(site, "radiometry"))
    assert re.search(r"<mfrac>(<mrow>)?<mn>1</mn>(</mrow>)?<mrow><msup><mi>e</mi><mrow><msub>"
                     r"<mi>c</mi><mn>2</mn></msub><mo>/</mo><mi>λ</mi><mi>T</mi></mrow></msup>"
                     r"<mo>−</mo><mn>1</mn></mrow></mfrac>", radiometry)
    # cases: a brace, then a table of two columns
    assert re.search(r"<mo>\{</mo><mtable><mtr><mtd>.*?</mtd><mtd>.*?</mtd></mtr>",
                     _mathml(brdf))
    # \mathrm{d} (days): upright, not italic
    assert '<mi mathvariant="normal">d</mi>' in _page(site, "platform")


def test_module_tables_are_tables(site):
    atmosphere = _page(site, "atmosphere")
    table = re.search(r"<table>\s*<thead>\s*<tr>\s*<th>name</th>\s*<th>unit</th>\s*"
                      r"<th>default</th>\s*<th>meaning</th>.*?</table>", atmosphere, re.S)
    assert table, "the uniform engine's parameter table"
    assert "<td><code>transmittance</code></td>" in table[0]
    assert "<td>W m-2 sr-1 um-1</td>" in table[0]
    brdf = _page(site, "brdf_models")
    assert re.search(r"<th>parameter</th>\s*<th>unit</th>\s*<th>default</th>", brdf)


def test_roles_become_links_or_code(site):
    pipeline = _page(site, "pipeline")
    # an object on a page: a link to it
    assert re.search(r'<a class="autorefs autorefs-internal"[^>]*href="#radscene\.pipeline\.'
                     r'render_hyperspectral"><code>render_hyperspectral</code></a>', pipeline)
    # one on none: its name as code
    assert re.search(r'<span title="radscene\.render\.integrator\.render"><code>radscene\.'
                     r"render\.integrator\.render</code></span>", pipeline)
    # across pages: a role in the registry's docstring to a model on the BRDF models page
    materials = _page(site, "materials")
    assert re.search(r'<a class="autorefs autorefs-internal"[^>]*href="\.\./brdf_models/#'
                     r'radscene\.materials\.brdf\.rpv\.RPV"><code>RPV</code></a>', materials)


#: The API pages of the heat balance, the platforms and the sensor chain, and a module each
#: must document.
NEW_PAGES = {
    "thermal": ("solve", "balance", "conduction", "convection", "evaporation", "exposure",
                "canopy", "radiation", "exchange", "lateral", "weather"),
    "platform": ("cameras", "scanners", "orbit", "geolocation", "trajectory", "motion"),
    "sensor_chain": ("chain", "channel", "sampling", "electronics", "processing", "config"),
}


@pytest.mark.parametrize("name", sorted(NEW_PAGES))
def test_heat_balance_platform_and_sensor_chain_pages(site, name):
    html = _page(site, name)
    package = {"thermal": "thermal", "platform": "platform", "sensor_chain": "sensor"}[name]
    for module in NEW_PAGES[name]:
        assert f'id="radscene.{package}.{module}"' in html, f"{name}: {module}"
    assert not RAW.findall(html), RAW.findall(html)[:5]
    # in the navigation of every page
    assert f'href="../{name}/"' in _page(site, "pipeline")
    # the numpydoc sections are parsed, not left as text
    assert "<td><code>" in html and not re.search(r"^-{4,}$", re.sub(r"<[^>]+>", "", html), re.M)


def test_heat_balance_page_typesets_its_equations(site):
    html = _page(site, "thermal")
    assert html.count('display="block"') >= 5
    for anchor in ("solve.solve_elements", "solve.ThermalOptions", "canopy",
                   "conduction"):
        assert f'id="radscene.thermal.{anchor}"' in html, anchor

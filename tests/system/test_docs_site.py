"""The documentation site builds in strict mode, and its API reference shows the docstrings'
reStructuredText as what it means: equations typeset by MathJax, tables as tables, roles as
links, no raw markup left."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mkdocstrings_handlers.python", reason="the site needs the docs extra")
pytest.importorskip("pymdownx.arithmatex", reason="the site needs the docs extra")

ROOT = Path(__file__).resolve().parents[2]
RAW = re.compile(r":(?:func|class|mod|meth|data|attr|math|obj|exc):`?<code>|:(?:func|class|mod|"
                 r"meth|data|attr|math):`|\.\. math::|^\s*(?:<p>)?=+(?: +=+)+|::</p>", re.M)


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


def test_equations_are_marked_for_mathjax(site):
    atmosphere = _page(site, "atmosphere")
    assert re.search(r'<div class="arithmatex">\\\[\s*L = L_\{path\}', atmosphere)
    brdf = _page(site, "brdf_models")
    assert brdf.count('<div class="arithmatex">') >= 20
    assert '<span class="arithmatex">\\(' in brdf  # inline math
    assert "tex-chtml.js" in brdf and "javascripts/mathjax.js" in brdf
    assert (site / "javascripts" / "mathjax.js").is_file()


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
    assert html.count('<div class="arithmatex">') >= 5
    for anchor in ("solve.solve_elements", "solve.ThermalOptions", "canopy",
                   "conduction"):
        assert f'id="radscene.thermal.{anchor}"' in html, anchor

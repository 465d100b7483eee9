"""The README's install lines work from a clone, list every extra, and the build requirements
can read pyproject.toml."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_the_readme_starts_with_make_demo_and_make_test():
    commands = re.findall(r"^make \w+", README, flags=re.M)
    assert commands[:2] == ["make demo", "make test"]


def test_no_install_line_names_a_package_that_is_not_on_pypi():
    """radscene is installed from its clone (``pip install '.[extra]'``), never by name."""
    texts = {"README.md": README}
    texts.update({str(p.relative_to(ROOT)): p.read_text(encoding="utf-8")
                  for p in (ROOT / "docs").rglob("*.md")})
    texts.update({str(p.relative_to(ROOT)): p.read_text(encoding="utf-8")
                  for p in (ROOT / "src").rglob("*.py")})
    bad = [f"{name}: {m.group(0)}" for name, text in texts.items()
           for m in re.finditer(r"pip install \S*radscene\S*", text)]
    assert not bad, bad
    assert "pip install '.[earthlib,zarr]'" in README


def test_the_readme_lists_every_extra_with_what_it_adds():
    extras = PYPROJECT["project"]["optional-dependencies"]
    rows = dict(re.findall(r"^\| `\[([\w-]+)\]` \| (.+) \|$", README, flags=re.M))
    assert set(rows) == set(extras), (sorted(rows), sorted(extras))
    assert all(len(text.strip()) > 10 for text in rows.values())


def test_the_build_requires_a_setuptools_that_reads_an_spdx_license():
    """A license given as an SPDX string (PEP 639) needs setuptools 77."""
    assert isinstance(PYPROJECT["project"]["license"], str)
    (setuptools,) = [r for r in PYPROJECT["build-system"]["requires"]
                     if r.startswith("setuptools")]
    low = re.fullmatch(r"setuptools>=(\d+)(\.\d+)*", setuptools.replace(" ", ""))
    assert low and int(low.group(1)) >= 77, setuptools

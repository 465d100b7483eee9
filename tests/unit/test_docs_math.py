r"""The documentation site's equations as MathML (``scripts/docs_math.py``): what arithmatex
marks becomes ``<math>`` elements, and what latex2mathml cannot convert, or converts into
something else without a sign, is named rather than shipped as raw TeX."""

from __future__ import annotations

import importlib.util
import re
import sys
from pathlib import Path

import pytest

pytest.importorskip("mkdocs", reason="the site's hooks need MkDocs (the docs extra)")
pytest.importorskip("latex2mathml", reason="the site's equations need latex2mathml (the docs "
                    "extra)")

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def math():
    spec = importlib.util.spec_from_file_location("docs_math", ROOT / "scripts" / "docs_math.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["docs_math"] = module
    spec.loader.exec_module(module)
    yield module
    sys.modules.pop("docs_math", None)


def _bare(mathml: str) -> str:
    """MathML without its attributes, for comparing structure."""
    return re.sub(r"<(/?[a-z]+)\b[^>]*?(/?)>", r"<\1\2>", mathml)


def test_display_and_inline(math):
    block = math.tex_to_mathml(r"\frac{a_1}{b}", display=True)
    assert block.startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">')
    assert "<mfrac><mrow><msub><mi>a</mi><mn>1</mn></msub></mrow><mrow><mi>b</mi></mrow></mfrac>" \
        in _bare(block)
    assert 'display="inline"' in math.tex_to_mathml("x")


def test_integral_with_limits(math):
    mathml = _bare(math.tex_to_mathml(r"\int_0^\infty f\,dx"))
    assert mathml.startswith("<math><mrow><msubsup><mo>&#x0222B;</mo><mn>0</mn>"
                             "<mo>&#x0221E;</mo></msubsup><mi>f</mi>")


def test_one_upright_letter_stays_upright(math):
    assert '<mi mathvariant="normal">d</mi>' in math.tex_to_mathml(r"365\ \mathrm{d}")
    assert '<mi mathvariant="normal">d</mi><mi>x</mi>' in math.tex_to_mathml(r"\mathrm{d}x")


@pytest.mark.parametrize(("tex", "reason"), [
    (r"\left( x", "latex2mathml: ExtraLeftOrMissingRightError"),
    (r"x^{", "braces do not pair"),
    (r"a}", "braces do not pair"),
    (r"\foo{x} + 1", r"left as TeX: \foo"),
    (r"\frac{a}", "<mfrac> with 1 argument(s), needs 2"),
])
def test_what_does_not_convert_is_named(math, tex, reason):
    with pytest.raises(math.UnconvertibleEquation, match=re.escape(reason)):
        math.tex_to_mathml(tex)


def test_a_page_converted(math):
    page = ('<p>For <span class="arithmatex">\\(a &lt; b\\)</span>:</p>\n'
            '<div class="arithmatex">\\[\nL = \\frac{1}{e^{x} - 1}\n\\]</div>\n'
            '<p>and <span class="arithmatex">\\(\\nope{x}\\)</span>.</p>')
    out = math.convert_html(page)
    assert (out.inline, out.display) == (1, 1)
    assert '<math xmlns="http://www.w3.org/1998/Math/MathML" display="inline"><mrow><mi>a</mi>' \
           "<mo>&#x0003C;</mo><mi>b</mi></mrow></math>" in out.html
    assert '<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">' in out.html
    assert out.failures == [(r"\nope{x}", r"left as TeX: \nope")]
    assert '<span class="arithmatex">\\(\\nope{x}\\)</span>' in out.html  # left as it was


def test_raw_tex_outside_equations(math):
    found = math.raw_tex("<p>then \\frac{a}{b} and $$x$$</p>")  # \frac, $$ and $$
    assert found == ["then \\frac{a}{b} and $$x$$"] * 3
    assert math.raw_tex("<p>run <code>printf '\\n'</code></p><pre>\\[x\\]</pre>"
                        '<a title="\\alpha">a</a>') == []

r"""The equations of the documentation site as MathML, made when the site is built.

A MkDocs hook (``mkdocs.yml``: ``hooks``). pymdownx.arithmatex (generic mode) marks the math of
the pages and of the docstrings (whose reStructuredText math ``scripts/griffe_rst.py`` writes as
``$...$`` and ``$$`` blocks): ``<span class="arithmatex">\(...\)</span>`` inline and
``<div class="arithmatex">\[...\]</div>`` for display. Each becomes a ``<math>`` element made by
latex2mathml (``display="block"`` for display math), which browsers render by themselves, so the
site shows its equations without a script or a network.

An equation latex2mathml cannot convert fails the build, with the page and the equation named:
one it raises on, one whose braces do not pair, one where a TeX command is left as text (an
unknown command comes out as ``<mi>\name</mi>``) and one where a fraction, root, script or
limit has the wrong number of arguments (``\frac{a}`` comes out as a fraction without a
denominator). So does TeX left in a page's text outside any marked equation (``\(``, ``\[``,
``$$`` or a command such as ``\frac``, outside code). No page ships raw TeX: the fix is to
write the equation, at its source, in a form latex2mathml converts. One form it converts
wrongly without a sign is rewritten before the conversion: ``\mathrm{d}`` (one letter), which
would show in italics, is converted as ``\mathrm d``.
"""

from __future__ import annotations

import html
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from mkdocs.exceptions import PluginError
from mkdocs.plugins import get_plugin_logger

__all__ = ["UnconvertibleEquation", "tex_to_mathml", "convert_html", "raw_tex"]

log = get_plugin_logger("docs_math")

#: What arithmatex writes in generic mode (its TeX escaped for HTML).
_MARKED = re.compile(r'<(?P<tag>span|div) class="arithmatex">(?P<tex>.*?)</(?P=tag)>', re.S)
#: The number of arguments of the MathML elements that take a fixed number.
_ARITY = {"mfrac": 2, "mroot": 2, "msub": 2, "msup": 2, "msubsup": 3, "munder": 2, "mover": 2,
          "munderover": 3}
_MATHML = "{http://www.w3.org/1998/Math/MathML}"
#: ``\mathrm{d}``: latex2mathml writes one upright letter as ``<mi>d</mi>``, which shows in
#: italics; ``\mathrm d`` it writes ``<mi mathvariant="normal">d</mi>``.
_ONE_UPRIGHT = re.compile(r"\\mathrm\{\s*([A-Za-z])\s*\}")
#: TeX in a page's text: math delimiters, or a command (a backslash and letters).
_RAW_TEX = re.compile(r"\\[([]|\$\$|\\[A-Za-z]+")
#: What may hold a backslash legitimately: code, scripts, styles and the MathML itself.
_VERBATIM = re.compile(r"<(?P<tag>code|pre|script|style|math)\b.*?</(?P=tag)>", re.S)


class UnconvertibleEquation(ValueError):
    """An equation latex2mathml cannot convert to MathML (the message says why)."""


def _braces_pair(tex: str) -> bool:
    depth = 0
    for char in re.sub(r"\\.", "", tex):  # \{ and \} are literal braces
        depth += {"{": 1, "}": -1}.get(char, 0)
        if depth < 0:
            return False
    return depth == 0


def tex_to_mathml(tex: str, display: bool = False) -> str:
    """One equation as a ``<math>`` element.

    Parameters
    ----------
    tex : str
        The equation's TeX, without delimiters.
    display : bool, optional
        Display math (``display="block"``) rather than inline.

    Returns
    -------
    str
        The MathML.

    Raises
    ------
    UnconvertibleEquation
        When latex2mathml raises on ``tex``, or its braces do not pair, or the MathML leaves a
        TeX command as text or gives an element the wrong number of arguments.
    """
    from latex2mathml.converter import convert

    if not _braces_pair(tex):
        raise UnconvertibleEquation("its braces do not pair")
    tex = _ONE_UPRIGHT.sub(r"\\mathrm \1", tex)
    try:
        mathml = convert(tex, display="block" if display else "inline")
    except Exception as error:  # latex2mathml's own errors, and any other it lets through
        raise UnconvertibleEquation(f"latex2mathml: {type(error).__name__} {error}".rstrip()) \
            from error
    try:
        tree = ET.fromstring(mathml)
    except ET.ParseError as error:
        raise UnconvertibleEquation(f"latex2mathml wrote MathML that does not parse: {error}") \
            from error
    left = sorted({word for element in tree.iter() for text in (element.text, element.tail)
                   if text for word in re.findall(r"\\[A-Za-z]+|\\.", text)})
    if left:
        raise UnconvertibleEquation(f"left as TeX: {' '.join(left)}")
    for element in tree.iter():
        name = element.tag.removeprefix(_MATHML)
        if name in _ARITY and len(element) != _ARITY[name]:
            raise UnconvertibleEquation(f"<{name}> with {len(element)} argument(s), "
                                        f"needs {_ARITY[name]}")
    return mathml


def _unmark(marked: str) -> str:
    """The TeX of an arithmatex element's content: unescaped, its delimiters removed."""
    tex = html.unescape(marked).strip()
    for left, right in (("\\(", "\\)"), ("\\[", "\\]")):
        if tex.startswith(left) and tex.endswith(right):
            return tex[len(left):-len(right)].strip()
    return tex  # a \begin{...} ... \end{...} block comes without delimiters


@dataclass
class Converted:
    """The outcome of :func:`convert_html`."""

    html: str
    inline: int = 0
    display: int = 0
    #: (equation, reason) of each equation left as it was.
    failures: list[tuple[str, str]] = field(default_factory=list)


def convert_html(text: str) -> Converted:
    """Every equation arithmatex marked in ``text`` as MathML.

    Parameters
    ----------
    text : str
        A page's HTML.

    Returns
    -------
    Converted
        The HTML with each equation that converts replaced by its ``<math>`` element (one that
        does not is left as it was, and listed with the reason), and the counts of inline and
        display equations converted.
    """
    out = Converted(text)

    def replace(match: re.Match) -> str:
        display = match["tag"] == "div"
        tex = _unmark(match["tex"])
        try:
            mathml = tex_to_mathml(tex, display)
        except UnconvertibleEquation as error:
            out.failures.append((tex, str(error)))
            return match[0]
        if display:
            out.display += 1
        else:
            out.inline += 1
        return mathml

    out.html = _MARKED.sub(replace, text)
    return out


def raw_tex(text: str) -> list[str]:
    r"""The TeX left in the text of a page's HTML: ``\(``, ``\[``, ``$$`` and commands such as
    ``\frac`` outside code, scripts, styles and MathML (tags and attributes are not text).

    Parameters
    ----------
    text : str
        A page's HTML.

    Returns
    -------
    list of str
        Each piece of TeX found, with a little of the text around it.
    """
    prose = html.unescape(re.sub(r"<[^>]*>", " ", _VERBATIM.sub(" ", text)))
    return [" ".join(prose[max(m.start() - 30, 0):m.end() + 30].split())
            for m in _RAW_TEX.finditer(prose)]


@dataclass
class _Build:
    """The equations of one build: the counts converted, and what failed on which page."""

    inline: int = 0
    display: int = 0
    pages: int = 0
    #: (page, equation or text, reason)
    failures: list[tuple[str, str, str]] = field(default_factory=list)


_build = _Build()


def on_pre_build(config) -> None:
    global _build
    _build = _Build()


def on_page_content(text: str, page, config, files) -> str:
    converted = convert_html(text)
    where = page.file.src_uri
    _build.inline += converted.inline
    _build.display += converted.display
    _build.pages += bool(converted.inline or converted.display)
    _build.failures += [(where, tex, reason) for tex, reason in converted.failures]
    _build.failures += [(where, found, "TeX outside any equation")
                        for found in raw_tex(_MARKED.sub(" ", converted.html))]
    return converted.html


def on_env(env, config, files):
    if _build.failures:
        lines = [f"  {page}: {tex!r}: {reason}" for page, tex, reason in _build.failures]
        raise PluginError(f"{len(lines)} piece(s) of TeX not converted to MathML (write each "
                          "so that latex2mathml converts it):\n" + "\n".join(lines))
    log.info("%d equations as MathML (%d inline, %d display) on %d pages",
             _build.inline + _build.display, _build.inline, _build.display, _build.pages)
    return env

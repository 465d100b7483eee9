"""The reStructuredText of radscene's numpydoc docstrings as Markdown, for the API reference.

A griffe extension (``mkdocs.yml``: the python handler's ``options.extensions``): once griffe
has loaded a package, the docstring of each of its objects is rewritten before mkdocstrings
parses and renders it, so the docstrings themselves stay numpydoc for ``help()``, IDEs and
doctests. What is converted:

- the roles naming an object (func, class, mod, meth, data, attr, obj, exc): an optional
  autoref (``<autoref identifier="radscene.full.path" optional>``) around the name as code,
  a link where that object is on a page of the site and the code alone where it is not or
  lies outside the package, so an object left out of the pages never fails a strict build;
- the math role: ``$...$``; the math directive: one ``$$`` block per equation (equations
  are separated by blank lines), both marked by pymdownx.arithmatex and made MathML when the
  site is built (``scripts/docs_math.py``);
- double-backquoted literals: single-backquoted code spans;
- simple tables (rules of ``=`` runs): Markdown tables, continuation lines (first column
  blank) joined into their row;
- a paragraph ending in ``::`` and the indented block after it: the paragraph ending in
  ``:`` and a fenced code block.

Doctests stay verbatim, and so do a docstring's numpydoc section headings. Brackets such as
``[0, 1] [-]`` (an interval, then a unit) are escaped so that Markdown does not read them as
a reference link. :func:`rst_to_markdown` is the conversion itself, usable without griffe.
"""

from __future__ import annotations

import re
import textwrap
from collections.abc import Callable

import griffe

__all__ = ["RstToMarkdown", "rst_to_markdown", "XREF_ROLES"]

#: Roles that name a Python object: converted to cross-references.
XREF_ROLES = frozenset({"func", "class", "mod", "meth", "data", "attr", "obj", "exc", "const",
                        "type"})

_ROLE = re.compile(r":(?:py:)?(?P<role>[a-z]+):`(?P<text>[^`]+)`")
_LITERAL = re.compile(r"``(?P<text>[^`]+?)``")
_CODE_OR_MATH = re.compile(r"(`+)[\s\S]+?\1|\$[^$]+\$")
#: "] [": Markdown would read "[0, 1] [-]" (an interval, then a unit) as a reference link.
_BRACKETS = re.compile(r"\]\s+\[")
_MATH = re.compile(r"^(?P<indent>\s*)\.\. math::\s*(?P<first>.*)$")
_DIRECTIVE = re.compile(r"^\s*\.\. [a-z-]+::")
_RULE = re.compile(r"^(?P<indent>\s*)=+(?: +=+)+\s*$")
_TITLED = re.compile(r"^(?P<title>.*?)\s*<(?P<target>[^<>]+)>$")

Resolver = Callable[[str], "str | None"]


def _indent_of(line: str) -> int:
    return len(line) - len(line.lstrip())


def _xref(text: str, resolve: Resolver) -> str:
    """A cross-reference role's text as an optional autoref (or code when unresolved)."""
    titled = _TITLED.match(text)
    title, target = (titled["title"], titled["target"]) if titled else (None, text)
    target = "".join(target.split())
    link = not target.startswith("!")
    target = target.lstrip("!~")
    if title is None:
        title = target.rsplit(".", 1)[-1] if text.strip().startswith("~") else target.lstrip(".")
    identifier = resolve(target) if link else None
    code = f"`{title}`"
    if identifier is None:
        return code
    return f'<autoref identifier="{identifier}" optional>{code}</autoref>'


def _inline(line: str, resolve: Resolver) -> str:
    """Roles and literals of one line of text."""

    def role(match: re.Match) -> str:
        name, text = match["role"], match["text"]
        if name == "math":
            return "$" + " ".join(text.split()) + "$"
        if name in XREF_ROLES:
            return _xref(text, resolve)
        return f"`{text}`"

    line = _ROLE.sub(role, line)
    line = _LITERAL.sub(lambda m: f"`{m['text']}`" if "`" not in m["text"] else m[0], line)
    return _outside_code(line, lambda text: _BRACKETS.sub(lambda m: m[0][:-1] + "\\[", text))


def _outside_code(text: str, edit: Callable[[str], str]) -> str:
    """``edit`` applied to the parts of ``text`` outside code spans and math."""
    out, pos = [], 0
    for match in _CODE_OR_MATH.finditer(text):
        out += [edit(text[pos:match.start()]), match[0]]
        pos = match.end()
    out.append(edit(text[pos:]))
    return "".join(out)


def _block(lines: list[str], start: int, indent: int) -> tuple[list[str], int]:
    """The lines from ``start`` indented deeper than ``indent`` (blank lines inside kept,
    trailing ones not), and the index after them."""
    end = start
    while end < len(lines) and (not lines[end].strip() or _indent_of(lines[end]) > indent):
        end += 1
    while end > start and not lines[end - 1].strip():
        end -= 1
    return lines[start:end], end


def _math(lines: list[str], i: int) -> tuple[list[str], int]:
    """A ``.. math::`` directive at ``lines[i]``: one ``$$`` block per equation."""
    match = _MATH.match(lines[i])
    pad, indent = match["indent"], len(match["indent"])
    body, end = _block(lines, i + 1, indent)
    body = [line for line in body if not line.strip().startswith(":")]  # :label:, :nowrap:
    text = (match["first"] + "\n" if match["first"].strip() else "") + textwrap.dedent(
        "\n".join(body))
    equations = [eq.strip() for eq in re.split(r"\n\s*\n", text) if eq.strip()]
    out = []
    for eq in equations:
        out += ["", f"{pad}$$", *(pad + row.strip() for row in eq.splitlines()), f"{pad}$$", ""]
    return out, end


def _cells(line: str, starts: list[int]) -> list[str]:
    bounds = [*starts[1:], None]
    return [line[a:b].strip() if b is not None else line[a:].strip()
            for a, b in zip(starts, bounds, strict=True)]


def _cell(text: str, resolve: Resolver) -> str:
    """A table cell's text as Markdown, pipes escaped (in math: written ``\\vert``)."""
    text = _inline(text, resolve)
    text = re.sub(r"\$[^$]+\$", lambda m: m[0].replace("|", r"\vert "), text)
    return _outside_code(text, lambda part: part.replace("|", "\\|"))


def _table(lines: list[str], i: int, resolve: Resolver) -> tuple[list[str], int] | None:
    """A simple table whose top rule is ``lines[i]``, or None when it is not one."""
    pad = _RULE.match(lines[i])["indent"]
    starts = [m.start() for m in re.finditer(r"=+", lines[i])]
    rules = [i]
    j = i + 1
    while j < len(lines) and len(rules) < 3:
        if _RULE.match(lines[j]):
            rules.append(j)
            if j + 1 >= len(lines) or not lines[j + 1].strip():
                break
        j += 1
    if len(rules) < 2:
        return None
    if len(rules) == 3:
        header_lines, body_lines = lines[rules[0] + 1:rules[1]], lines[rules[1] + 1:rules[2]]
    else:
        header_lines, body_lines = [], lines[rules[0] + 1:rules[1]]

    def rows(block: list[str]) -> list[list[str]]:
        out: list[list[str]] = []
        for line in block:
            if not line.strip():
                continue
            cells = _cells(line, starts)
            if out and not cells[0]:  # a continuation line
                out[-1] = [f"{a} {b}".strip() for a, b in zip(out[-1], cells, strict=True)]
            else:
                out.append(cells)
        return out

    header = [" ".join(c) for c in zip(*rows(header_lines), strict=True)] if header_lines \
        else [""] * len(starts)
    table = ["", pad + "| " + " | ".join(_cell(c, resolve) for c in header) + " |",
             pad + "|" + "|".join(" --- " for _ in starts) + "|"]
    table += [pad + "| " + " | ".join(_cell(c, resolve) for c in row) + " |"
              for row in rows(body_lines)]
    return table + [""], rules[-1] + 1


def _literal(lines: list[str], i: int, resolve: Resolver) -> tuple[list[str], int]:
    """A paragraph line ending in ``::`` and the indented block after it as a fenced block."""
    line = lines[i]
    indent = _indent_of(line)
    stripped = line.rstrip()
    if stripped.strip() == "::":
        head = []
    elif stripped.endswith(" ::"):
        head = [_inline(stripped[:-3], resolve)]
    else:
        head = [_inline(stripped[:-1], resolve)]
    j = i + 1
    while j < len(lines) and not lines[j].strip():
        j += 1
    body, end = _block(lines, j, indent)
    if not body:
        return head, i + 1
    pad = " " * indent
    code = textwrap.dedent("\n".join(body)).splitlines()
    return [*head, "", pad + "```", *((pad + c).rstrip() for c in code), pad + "```", ""], end


def _special(lines: list[str], i: int) -> bool:
    """Whether ``lines[i]`` starts a construct of its own (math, table, literal block)."""
    line = lines[i]
    return bool(_MATH.match(line) or _RULE.match(line) or line.lstrip().startswith("```")
                or (line.rstrip().endswith("::") and not _DIRECTIVE.match(line)))


def rst_to_markdown(text: str, resolve: Resolver | None = None) -> str:
    """The reStructuredText constructs of a numpydoc docstring as Markdown.

    Parameters
    ----------
    text : str
        A docstring (cleaned: its common indentation removed).
    resolve : callable, optional
        ``resolve(name) -> identifier or None``: the full path of an object a role names, for
        a cross-reference; None (or no resolver) writes the name as code.

    Returns
    -------
    str
        The docstring with its sections (``Parameters`` and its dashes) left as they are.
    """
    resolve = resolve or (lambda name: None)
    lines = text.splitlines()
    out: list[str] = []
    i = 0
    fence = False
    while i < len(lines):
        line = lines[i]
        if line.lstrip().startswith("```"):
            fence = not fence
        if fence:
            out.append(line)
            i += 1
            continue
        if _MATH.match(line):
            block, i = _math(lines, i)
            if out and out[-1].strip() and _indent_of(out[-1]) < _indent_of(line):
                block = block[1:]  # the description of a section item: no blank line before
        elif _RULE.match(line) and (i == 0 or not lines[i - 1].strip()) \
                and (table := _table(lines, i, resolve)) is not None:
            block, i = table
        elif line.rstrip().endswith("::") and not _DIRECTIVE.match(line):
            block, i = _literal(lines, i, resolve)
        else:  # ordinary text: converted a paragraph at a time (a role may span lines)
            start = i
            while i < len(lines) and lines[i].strip() and not _special(lines, i):
                i += 1
            i = max(i, start + 1)
            # a doctest stays verbatim, its output too, also where a heading ("Examples" and
            # its dashes) runs into it without a blank line
            doctest = next((k for k in range(start, i) if lines[k].lstrip().startswith(">>>")), i)
            block = _inline("\n".join(lines[start:doctest]), resolve).split("\n") \
                if doctest > start else []
            block += lines[doctest:i]
        out.extend(block)
    return re.sub(r"\n{3,}", "\n\n", "\n".join(out)).strip("\n")


def _objects(obj: griffe.Object):
    """``obj`` and every object defined under it (aliases left out)."""
    yield obj
    for member in obj.members.values():
        if not member.is_alias:
            yield from _objects(member)


def _tails(package: griffe.Module) -> dict[str, set[str]]:
    """The last one, two and three components of each object path of ``package`` -> paths."""
    tails: dict[str, set[str]] = {}
    for obj in _objects(package):
        parts = obj.path.split(".")
        for n in (1, 2, 3):
            if len(parts) > n:
                tails.setdefault(".".join(parts[-n:]), set()).add(obj.path)
    return tails


def _resolver(obj: griffe.Object, collection, tails: dict[str, set[str]]) -> Resolver:
    """``resolve(name)`` for the roles of ``obj``'s docstring: the canonical path of the object
    the name means in ``obj``'s scope (as Python would see it), else of the one object of the
    package whose path ends with the name; None when there is none or several."""

    def resolve(name: str) -> str | None:
        name = name.strip().removesuffix("()").lstrip(".")
        first, _, rest = name.partition(".")
        try:
            base = obj.resolve(first)
        except griffe.NameResolutionError:
            base = first
        paths = [f"{base}.{rest}" if rest else base, name]
        if len(tails.get(name, ())) == 1:
            paths += list(tails[name])
        for path in paths:
            try:
                return collection.get_member(path).canonical_path
            except (KeyError, ValueError, griffe.AliasResolutionError, griffe.CyclicAliasError):
                continue
        return None

    return resolve


class RstToMarkdown(griffe.Extension):
    """Rewrites the docstrings of every object of a loaded package from RST to Markdown."""

    def on_package(self, *, pkg: griffe.Module, loader: griffe.GriffeLoader, **kwargs) -> None:
        tails = _tails(pkg)
        for obj in list(_objects(pkg)):
            if obj.docstring is not None:
                resolve = _resolver(obj, loader.modules_collection, tails)
                obj.docstring.value = rst_to_markdown(obj.docstring.value, resolve)

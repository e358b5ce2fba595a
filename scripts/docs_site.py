"""The documentation site's two pieces of glue (``mkdocs.yml`` names this file).

As a MkDocs hook (``hooks:``): the pages link the shipped runs' figures and
``results.md`` pages where they are in the repository
(``../results/long-seed0/composed/eval/composed.png``), so the links also
work on a forge's file view; :func:`on_files` copies those files into the
site under ``shipped/`` and lets MkDocs check every such link like any
other.

As a Griffe extension (:class:`RstDocstrings`, the API reference's
``extensions:``): the package's docstrings are written for the terminal and
``help()``, with a few reStructuredText habits — Sphinx roles
(``:func:`~locustjump.train```), simple tables between ``=====`` rules and
``::`` before a literal block. It rewrites those into Markdown before
mkdocstrings renders them; nothing else in a docstring changes.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import griffe
from mkdocs.config.defaults import MkDocsConfig
from mkdocs.structure.files import File, Files, InclusionLevel

ROOT = Path(__file__).resolve().parents[1]
#: what the site takes from results/: figures, and results.md as plain text
SHIPPED = ("*.png", "*.mp4", "results.md", "references.md")


class _Shipped(File):
    """A file of ``results/``, linked as ``../results/...``, copied as is."""

    def is_documentation_page(self) -> bool:
        return False


def on_files(files: Files, config: MkDocsConfig) -> Files:
    for pattern in SHIPPED:
        for path in sorted((ROOT / "results").rglob(pattern)):
            rel = path.relative_to(ROOT).as_posix()
            f = _Shipped(
                f"../{rel}",
                str(ROOT / "docs"),
                config["site_dir"],
                config["use_directory_urls"],
                dest_uri=f"shipped/{rel}",
                inclusion=InclusionLevel.INCLUDED,
            )
            files.append(f)
    return files


_ROLE = re.compile(r":(?:mod|func|class|meth|attr|data|exc|obj):`(~?)\.?([\w.]+)`")
_RULE = re.compile(r"^( *)(=+)(?: +=+)+ *$")


def _role(m: re.Match[str]) -> str:
    short, path = m.groups()
    return f"`{path.rsplit('.', 1)[-1] if short else path}`"


def _columns(rule: str) -> list[tuple[int, int]]:
    return [(m.start(), m.end()) for m in re.finditer(r"=+", rule)]


def _cells(line: str, cols: list[tuple[int, int]]) -> list[str]:
    """A row's cells; the last column runs to the end of the line."""
    starts = [a for a, _ in cols] + [len(line) + 1]
    return [line[starts[i] : starts[i + 1]].strip() for i in range(len(cols))]


def _rows(lines: list[str], cols: list[tuple[int, int]]) -> list[list[str]]:
    """The rows between two rules; a line whose first cell is blank
    continues the row above it."""
    rows: list[list[str]] = []
    for line in lines:
        if not line.strip():
            continue
        cells = _cells(line, cols)
        if rows and not cells[0]:
            rows[-1] = [
                f"{a} {b}".strip() for a, b in zip(rows[-1], cells, strict=True)
            ]
        else:
            rows.append(cells)
    return rows


def _pipe(indent: str, row: list[str]) -> str:
    return indent + "| " + " | ".join(c.replace("|", "\\|") for c in row) + " |"


def rst_tables_to_markdown(text: str) -> str:
    """Every simple reStructuredText table of ``text`` in Markdown: a table
    with a header (a rule, the header, a rule, rows, a rule) as a pipe table,
    one without (a rule, rows, a rule) as a list of its rows."""
    lines, out, i = text.split("\n"), [], 0
    while i < len(lines):
        m = _RULE.match(lines[i])
        rules = [j for j in range(i + 1, len(lines)) if _RULE.match(lines[j])]
        if not m or not rules:
            out.append(lines[i])
            i += 1
            continue
        indent, cols = m.group(1), _columns(lines[i])
        if rules[0] == i + 2 and len(rules) >= 2:  # a header row
            end = rules[1]
            out.append(_pipe(indent, _cells(lines[i + 1], cols)))
            out.append(indent + "|" + " --- |" * len(cols))
            out += [_pipe(indent, r) for r in _rows(lines[i + 3 : end], cols)]
        else:
            end = rules[0]
            for first, *rest in _rows(lines[i + 1 : end], cols):
                out.append(f"{indent}- {first}: {' '.join(rest)}")
        i = end + 1
    return "\n".join(out)


def rst_to_markdown(text: str) -> str:
    """Sphinx roles as code spans, simple tables as pipe tables, ``::`` as ``:``."""
    text = rst_tables_to_markdown(text)  # first: a role's width is its column's
    text = _ROLE.sub(_role, text)
    text = re.sub(r"(?m)^ *::\n", "\n", text)  # a lone '::' line
    return re.sub(r"(?<=\S)::(?=\n\n)", ":", text)


class RstDocstrings(griffe.Extension):
    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = rst_to_markdown(obj.docstring.value)

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

import griffe
from mkdocs.structure.files import File, Files, InclusionLevel

ROOT = Path(__file__).resolve().parents[1]
#: what the site takes from results/: figures, and results.md as plain text
SHIPPED = ("*.png", "*.mp4", "results.md", "references.md")


class _Shipped(File):
    """A file of ``results/``, linked as ``../results/...``, copied as is."""

    def is_documentation_page(self) -> bool:
        return False


def on_files(files: Files, config) -> Files:
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


def _role(m: re.Match) -> str:
    short, path = m.groups()
    return f"`{path.rsplit('.', 1)[-1] if short else path}`"


def _columns(rule: str) -> list[tuple[int, int]]:
    return [(m.start(), m.end()) for m in re.finditer(r"=+", rule)]


def _cells(line: str, cols: list[tuple[int, int]]) -> list[str]:
    """A row's cells; the last column runs to the end of the line."""
    starts = [a for a, _ in cols] + [len(line) + 1]
    return [line[starts[i] : starts[i + 1]].strip() for i in range(len(cols))]


def rst_tables_to_markdown(text: str) -> str:
    """Every simple reStructuredText table (a rule, a header row, a rule,
    rows, a closing rule) of ``text`` as a Markdown pipe table."""
    lines, out, i = text.split("\n"), [], 0
    while i < len(lines):
        m = _RULE.match(lines[i])
        rules = [j for j in range(i, min(len(lines), i + 200)) if _RULE.match(lines[j])]
        if m and len(rules) >= 3 and lines[rules[1]] == lines[i]:
            indent, cols = m.group(1), _columns(lines[i])
            header = _cells(lines[i + 1], cols)
            end = rules[2]
            body = [
                _cells(row, cols) for row in lines[rules[1] + 1 : end] if row.strip()
            ]
            out.append(indent + "| " + " | ".join(header) + " |")
            out.append(indent + "|" + " --- |" * len(cols))
            for row in body:
                cells = (c.replace("|", "\\|") for c in row)
                out.append(indent + "| " + " | ".join(cells) + " |")
            i = end + 1
            continue
        out.append(lines[i])
        i += 1
    return "\n".join(out)


def rst_to_markdown(text: str) -> str:
    """Sphinx roles as code spans, simple tables as pipe tables, ``::`` as ``:``."""
    text = _ROLE.sub(_role, text)
    text = rst_tables_to_markdown(text)
    text = re.sub(r"(?m)^ *::\n", "\n", text)  # a lone '::' line
    return re.sub(r"(?<=\S)::(?=\n\n)", ":", text)


class RstDocstrings(griffe.Extension):
    def on_instance(self, *, obj: griffe.Object, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = rst_to_markdown(obj.docstring.value)

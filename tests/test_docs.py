"""The documentation site: it builds in strict mode (a broken link, anchor or
API reference fails), its API reference covers the public API, and the
README's links, which the site's build does not read, point at what exists.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import re
import subprocess
import sys

import pytest

import locustjump
from docpages import DOCS, PAGES, README, ROOT, headings, links

API = DOCS / "api"


def _site_hook():
    spec = importlib.util.spec_from_file_location(
        "docs_site", ROOT / "scripts" / "docs_site.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_site_builds_in_strict_mode(tmp_path):
    """``make docs``: ``mkdocs build --strict`` (every page, link, anchor and
    ``::: identifier`` of the API reference) into a fresh directory."""
    pytest.importorskip("mkdocstrings", reason="extra locustjump[docs] not installed")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    r = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
         str(tmp_path / "site")],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    site = tmp_path / "site"
    assert (site / "api" / "sim" / "index.html").is_file()
    # the API reference rendered the docstrings, not only the headings
    html = (site / "api" / "envs" / "index.html").read_text()
    assert "LocustKick-v0" in html and "<table>" in html
    # the shipped figures the pages show are in the site
    assert list((site / "shipped" / "results").rglob("composed.png"))


def test_every_public_name_has_its_api_entry():
    """Each name of ``locustjump.__all__`` has a ``::: module.name`` entry in
    the API reference that is the very object ``locustjump.name`` gives (a
    new export without an entry fails here, a wrong path in the strict
    build)."""
    text = "\n".join(p.read_text() for p in API.glob("*.md"))
    entries = re.findall(r"(?m)^::: ([\w.]+)$", text)
    missing = []
    for name in locustjump.__all__:
        if name == "__version__":
            continue
        documented = [
            getattr(importlib.import_module(e.rpartition(".")[0]), name, None)
            for e in entries
            if e.rpartition(".")[2] == name
        ]
        if not any(d is getattr(locustjump, name) for d in documented):
            missing.append(name)
    assert not missing, missing


def _github_slug(heading: str) -> str:
    """A heading's anchor as a forge (GitHub) writes it."""
    s = re.sub(r"`|\*\*|\*", "", heading).strip().lower()
    s = "".join(c for c in s if c.isalnum() or c in " -_")
    return s.replace(" ", "-")


def _site_slug(heading: str) -> str:
    """As the site writes it (``markdown``'s ``slugify_unicode``)."""
    from markdown.extensions.toc import slugify_unicode

    return slugify_unicode(re.sub(r"`|\*\*|\*", "", heading), "-")


def test_every_heading_has_one_anchor_on_the_site_and_the_forge():
    """A link to a heading works in both places only where both write its
    anchor alike (no ' — ' in a heading: the forge keeps two hyphens)."""
    pytest.importorskip("markdown", reason="extra locustjump[docs] not installed")
    differ = [
        (page.relative_to(ROOT), h)
        for page in PAGES
        for h in headings(page)
        if _github_slug(h) != _site_slug(h)
    ]
    assert not differ, differ


def test_the_readmes_links_point_at_what_exists():
    """The README is not part of the site: its relative links and their
    anchors are checked here (the site's build checks the pages')."""
    broken = []
    for _label, target in links(README):
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        file = ROOT / path if path else README
        if not file.exists():
            broken.append(target)
        elif anchor and anchor not in {_github_slug(h) for h in headings(file)}:
            broken.append(target)
    assert not broken, broken


def test_the_api_reference_reads_the_docstrings_as_markdown():
    """scripts/docs_site.py: a docstring's Sphinx roles become code spans, a
    simple table a pipe table (without a header: a list), '::' before a
    literal block a colon."""
    hook = _site_hook()
    doc = """Train :func:`~locustjump.runs.trainer.train` into :mod:`lj.rundir`::

    =====  ======  =====
    index  what    unit
    =====  ======  =====
    0      hip     rad
    4      touch   -
    =====  ======  =====

Done."""
    md = hook.rst_to_markdown(doc)
    assert "`train`" in md and "`lj.rundir`" in md and ":func:" not in md
    assert "| index | what | unit |" in md
    assert "| 0 | hip | rad |" in md and "| 4 | touch | - |" in md
    assert "=====" not in md and "rundir`:\n" in md
    hooks = """Hooks:

    =========  =====================
    :meth:`a`  the first, which runs
               over two lines
    ``b``      the second
    =========  =====================
"""
    md = hook.rst_to_markdown(hooks)
    assert "- `a`: the first, which runs over two lines\n" in md
    assert "- ``b``: the second" in md and "=====" not in md


def test_the_site_copies_the_shipped_figures_it_links():
    """The pages link ``../results/...``; the hook makes each such file part
    of the site, so the strict build checks those links too."""
    pytest.importorskip("mkdocs", reason="extra locustjump[docs] not installed")
    from mkdocs.structure.files import Files

    hook = _site_hook()
    files = hook.on_files(
        Files([]), {"site_dir": "/nonexistent", "use_directory_urls": True}
    )
    figure = "../results/paper-seed0/composed/eval/composed.png"
    f = files.get_file_from_path(figure)
    assert f is not None and f.dest_uri == figure.replace("..", "shipped", 1)
    assert f.abs_src_path == str(ROOT / figure[3:])
    assert not f.is_documentation_page()
    used = {t for p in PAGES if p != README for _, t in links(p)}
    assert figure in used


def test_the_changelog_is_the_site_page():
    assert (DOCS / "changelog.md").read_text().strip() == '--8<-- "CHANGELOG.md"'
    text = (ROOT / "CHANGELOG.md").read_text()
    assert f"been {locustjump.__version__}" in text


def test_the_readmes_claims_are_the_shipped_runs():
    """Every number of the README's 'what reproduces' table ('here') is one
    of the shipped files it cites: the paper-budget reproduction's
    results.md and the flat-composition, debris-composition and both
    repertoire studies' tables."""
    shipped = (ROOT / "results" / "paper-seed0" / "results.md").read_text()
    for study in (
        "flat-composition",
        "debris-composition",
        "repertoire-composition",
        "repertoire-composition-debris",
    ):
        shipped += (ROOT / "results" / "studies" / study / "table.md").read_text()
    numbers = set(re.findall(r"\d+(?:\.\d+)?", shipped))
    section = README.read_text().split("## What reproduces", 1)[1].split("\n## ")[0]
    rows = [r.split("|") for r in section.splitlines() if r.startswith("| ")]
    assert len(rows) >= 8, rows
    for row in rows[2:]:
        for n in re.findall(r"\d+(?:\.\d+)?", row[2]):
            assert n in numbers, f"README: {n} ({row[2].strip()}) is in no shipped file"

"""``locustjump report``: one self-contained HTML page, checked in headless
Chromium (Debian package ``chromium``) where it is installed."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from locustjump.cli import main
from locustjump.present.report import markdown_to_html, write_report


def _chromium() -> str:
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if path := shutil.which(name):
            return path
    pytest.skip("headless Chromium not installed (Debian package chromium)")


def _images_in_browser(page: Path) -> tuple[int, int]:
    """(decoded, total) images of ``page`` as headless Chromium loads it."""
    dom = subprocess.run(
        [_chromium(), "--headless", "--no-sandbox", "--disable-gpu",
         "--dump-dom", page.as_uri()],
        capture_output=True, text=True, timeout=120, check=True,
    ).stdout  # fmt: skip
    m = re.search(r'<body data-images="(\d+)/(\d+)"', dom)
    assert m, "the page's load handler did not run"
    return int(m.group(1)), int(m.group(2))


@pytest.fixture
def run_copy(shipped, tmp_path) -> Path:
    return shutil.copytree(shipped / "kick", tmp_path / "kick")


def test_run_report_is_self_contained(run_copy, capsys):
    assert main(["report", str(run_copy)]) == 0
    page = run_copy / "report.html"
    text = page.read_text()
    assert "report.html" in capsys.readouterr().out
    # config, training summary, metrics of the re-simulated best genome
    # config.toml and the metrics as tables (a section, a dict: a nested table)
    assert "<th>rcga</th><td><table><tr><th>population</th><td>50</td>" in text
    assert "wall time (s)" in text and "<pre>" not in text
    assert "<th>apex height ratio to rules</th>" in text
    assert "<th>takeoff speed (m/s)</th>" in text and "{" not in text.split("<body")[1]
    assert "<td>True</td>" in text  # re-simulated fitness matches the record
    # everything embedded: no file or network reference
    srcs = re.findall(r'src="([^"]*)"', text)
    assert len(srcs) >= 2 and all(s.startswith("data:") for s in srcs)
    assert "http://" not in text and "https://" not in text


def test_run_report_renders_in_chromium(run_copy):
    page = write_report(run_copy)
    loaded, total = _images_in_browser(page)
    assert total >= 2 and loaded == total


def test_reproduction_report_has_the_results_table(shipped, tmp_path):
    d = shutil.copytree(shipped, tmp_path / "rep")
    page = write_report(d)
    text = page.read_text()
    assert "<h2>The paper&#x27;s claims</h2>" in text or "The paper's claims" in text
    assert text.count("<table>") >= 3 + 5  # results.md tables + one per stage
    assert "Stage composed" in text and "missing figure" not in text
    loaded, total = _images_in_browser(page)
    assert total >= 15 and loaded == total


def test_markdown_by_the_library(tmp_path):
    (tmp_path / "f.png").write_bytes(b"\x89PNG")
    html = markdown_to_html(
        "# T\n\nA `x` and **y**\nmore.\n\n| a | b |\n| --- | --- |\n| 1 | <2> |\n"
        "\nWhy:\n\n- one: `a`\n- two\n\n![fig](f.png) ![gone](nope.png)\n\n"
        "[seed 0](seed-0/results.md)\n",
        tmp_path,
    )
    assert "<h1>T</h1>" in html
    assert "<p>A <code>x</code> and <strong>y</strong>\nmore.</p>" in html
    assert "<th>a</th>" in html and "<td>&lt;2&gt;</td>" in html
    assert "<ul>\n<li>one: <code>a</code></li>\n<li>two</li>\n</ul>" in html
    assert 'src="data:image/png;base64,' in html and "(missing figure nope.png)" in html
    assert 'href="seed-0/report.html"' in html


def test_report_bad_input(tmp_path, capsys):
    assert main(["report", str(tmp_path / "nope")]) == 2
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and "no such directory" in err[0] and "holds no run" in err[1]
    assert not (tmp_path / "report.html").exists()

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
    assert "[rcga]" in text and "wall time (s)" in text
    assert "apex_height_ratio_to_rules" in text
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


def test_markdown_subset():
    html = markdown_to_html(
        "# T\n\nA `x` and **y**\nmore.\n\n| a | b |\n| --- | --- |\n| 1 | <2> |\n",
        Path("."),
    )
    assert "<h1>T</h1>" in html
    assert "<p>A <code>x</code> and <strong>y</strong> more.</p>" in html
    assert "<th>a</th>" in html and "<td>&lt;2&gt;</td>" in html


def test_report_bad_input(tmp_path, capsys):
    assert main(["report", str(tmp_path / "nope")]) == 2
    assert main(["report", str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and "no such directory" in err[0] and "holds no run" in err[1]
    assert not (tmp_path / "report.html").exists()

"""``scripts/mutation.py`` writes ``docs/mutation.md``: a module run here
replaces its row and its mutants; a module not run on this machine keeps
what the page says of it (a fresh clone has no scratch results)."""

import importlib.util
import re
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))  # mutation.py imports its neighbours
_spec = importlib.util.spec_from_file_location(
    "mutation_script", REPO / "scripts" / "mutation.py"
)
mutation = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(mutation)

ROW = re.compile(r"^\| .+ \|$", re.M)


@pytest.fixture
def page(tmp_path, monkeypatch):
    """The shipped page, copied where write_doc writes, and no scratch
    results (no module has run here)."""
    doc = tmp_path / "mutation.md"
    doc.write_text((REPO / "docs" / "mutation.md").read_text())
    monkeypatch.setattr(mutation, "DOC", doc)
    monkeypatch.setattr(mutation, "LAST_RUN", tmp_path / "absent.txt")
    return doc


def test_module_of_reads_functions_methods_and_packages():
    assert mutation.module_of("locustjump.evo.rcga.x_blx__mutmut_3") == "evo/rcga.py"
    assert (
        mutation.module_of("locustjump.tasks.kick.xǁKickRewardǁ__call____mutmut_1")
        == "tasks/kick.py"
    )
    assert mutation.module_of("locustjump.evo.x_register__mutmut_23") == (
        "evo/__init__.py"
    )
    assert mutation.module_of("locustjump.present.plots.x_f__mutmut_1") is None


def test_a_page_written_without_results_is_the_page(page):
    before = page.read_text()
    mutation.write_doc({m: None for m in mutation.MODULES})
    assert page.read_text() == before
    assert "| not run |" not in before


def test_a_row_without_its_minutes_is_kept_too(page):
    """A module whose wall time was not recorded shows ``nan`` minutes: its
    row and mutants are still the page's."""
    rcga = "| evo/rcga.py | 375 | 359 | 16 | 0 | 100.0 % | 2.2 |"
    text = page.read_text()
    assert rcga in text
    page.write_text(text.replace(rcga, rcga.replace("2.2 |", "nan |")))
    mutation.write_doc({m: None for m in mutation.MODULES})
    after = page.read_text()
    assert "| evo/rcga.py | 375 | 359 | 16 | 0 | 100.0 % | nan |" in after
    assert after.count("- equivalent `locustjump.evo.rcga.") == 16


def test_a_module_run_here_replaces_its_row_and_mutants_only(page):
    before = page.read_text()
    run: mutation.Summary = {
        "mutants": 10,
        "killed": 8,
        "equivalent": [("locustjump.evo.cma.x_f__mutmut_1", "- a | + b", "why")],
        "survived": [("locustjump.evo.cma.x_f__mutmut_2", "- c | + d")],
        "wall": 90.0,
    }
    results = {m: None for m in mutation.MODULES}
    results["evo/cma.py"] = run
    mutation.write_doc(results)
    after = page.read_text()
    rows = dict(zip(ROW.findall(before), ROW.findall(after), strict=True))
    changed = {a: b for a, b in rows.items() if a != b}
    assert list(changed.values())[0] == (
        "| evo/cma.py | 10 | 8 | 1 | 1 | 88.9 % | 1.5 |"
    )
    assert len(changed) == 2 and list(changed)[1].startswith("| all |")
    cma = [ln for ln in after.splitlines() if "locustjump.evo.cma." in ln]
    assert cma == [
        "- equivalent `locustjump.evo.cma.x_f__mutmut_1`: `- a | + b` — why",
        "- **survived** `locustjump.evo.cma.x_f__mutmut_2`: `- c | + d`",
    ]
    # every other module's mutants are kept, as they were
    others = [
        ln
        for ln in before.splitlines()
        if ln.startswith("- ") and "locustjump.evo.cma." not in ln
    ]
    assert all(ln in after for ln in others)


def test_without_a_page_a_module_not_run_says_so(page):
    page.unlink()
    mutation.write_doc({m: None for m in mutation.MODULES})
    assert page.read_text().count("| not run |") == len(mutation.MODULES)


def test_the_page_names_every_module_outside_the_table(monkeypatch):
    src = REPO / "src" / "locustjump"
    every = {str(f.relative_to(src)) for f in src.rglob("*.py")}
    text = mutation.not_mutated()
    outside = set(re.findall(r"`([^`]+)`", text))
    assert outside == every - set(mutation.MODULES)
    assert f"{len(outside)} of the package's {len(every)} modules" in text
    monkeypatch.setitem(mutation.MODULES, "cli/parser.py", ())
    assert "`cli/parser.py`" not in mutation.not_mutated()

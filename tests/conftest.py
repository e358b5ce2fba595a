import os
from pathlib import Path

# isort: off
import locustjump  # noqa: F401  (first: it picks MUJOCO_GL before mujoco loads)

# isort: on
import mujoco
import numpy as np
import pytest

from helpers import TINY_GENERATIONS, example_study, run_cli
from locustjump.sim import model as lm


@pytest.fixture(scope="session")
def params() -> lm.LocustParams:
    return lm.LocustParams()


@pytest.fixture(scope="session")
def mjmodel(params) -> mujoco.MjModel:
    return lm.load_model(params)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1234)


@pytest.fixture(scope="session")
def render_problem(mjmodel) -> str | None:
    """Why offscreen rendering fails here (one line), or None where a frame
    can be drawn (no libegl1, or ``MUJOCO_GL=disable`` as the mutation runs
    set it)."""
    from locustjump.present.render import RenderUnavailable, make_renderer

    try:
        make_renderer(mjmodel, 32, 24).close()
    except RenderUnavailable as e:
        return str(e)
    return None


#: the shipped reproduction (genomes evolved by `locustjump reproduce`)
SHIPPED = Path(__file__).resolve().parent.parent / "results" / "quick-seed0"


@pytest.fixture(scope="session")
def shipped() -> Path:
    if not (SHIPPED / "reproduce.toml").is_file():
        pytest.skip(f"{SHIPPED} not present")
    return SHIPPED


@pytest.fixture(scope="session")
def tiny_reproduction(tmp_path_factory):
    """``tiny_reproduction(seed)``: a reproduction of every stage on the tiny
    budget (population 4, 1 generation a stage, no videos), made once per
    session and shared by every test file that needs one (about half a
    minute each). Treat it as read-only: a test that changes one works on a
    copy."""
    from locustjump.runs.reproduce import Budget, reproduce

    budget = Budget("tiny", 4, TINY_GENERATIONS)
    made: dict[int, Path] = {}

    def make(seed: int) -> Path:
        if seed not in made:
            out = tmp_path_factory.mktemp("tiny") / f"s{seed}"
            reproduce(out, budget=budget, seed=seed, progress=False,
                      log=lambda s: None, videos=False)  # fmt: skip
            made[seed] = out
        return made[seed]

    return make


@pytest.fixture(scope="session")
def local_ray():
    """One local Ray instance (2 CPUs) for the whole test session."""
    ray = pytest.importorskip("ray", reason="Ray is not installed (locustjump[ray])")
    if not ray.is_initialized():
        ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False,
                 configure_logging=False)  # fmt: skip
    yield ray
    ray.shutdown()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """With LOCUSTJUMP_NO_SKIP set (CI, which installs every system package
    the README lists), a skipped test fails: every test must run there."""
    outcome = yield
    report = outcome.get_result()
    if (
        report.skipped
        and os.environ.get("LOCUSTJUMP_NO_SKIP")
        and not hasattr(report, "wasxfail")
    ):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else ""
        report.outcome = "failed"
        report.longrepr = f"skipped in CI, where every test must run: {reason}"


@pytest.fixture(scope="session")
def finished_study(tmp_path_factory):
    """The example study (``helpers.example_study``), trained and tabled once
    a session: ``(study file, the train's and the table's CompletedProcess)``.
    Read-only: a test that changes it works on a copy."""
    tmp = tmp_path_factory.mktemp("study")
    path = example_study(tmp)
    r = run_cli("study", str(path), "--quiet", "--threads", "2")
    assert r.returncode == 0, r.stderr
    t = run_cli("study", str(path), "--table", "--quiet")
    assert t.returncode == 0, t.stderr
    return path, r, t


@pytest.fixture
def formula(monkeypatch):
    """The formula behaviours (``tests/formula.py``) registered, their
    counters reset."""
    from formula import Formula, FormulaComposed
    from locustjump import tasks

    monkeypatch.setattr(tasks, "_REGISTRY", dict(tasks._REGISTRY))
    tasks.register_behaviour(Formula)
    tasks.register_behaviour(FormulaComposed)
    Formula.reset()
    return Formula

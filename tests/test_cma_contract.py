"""CMA-ES over pycma (evo/cma.py) stated exactly: its settings' ranges, its
first sample (the mean 0 plus sigma0 times the run's own normal draws), a
quiet pycma that writes no files, the state's checks, and the message when
pycma is missing (issue #48, scripts/mutation.py)."""

import re
import sys

import numpy as np
import pytest

pytest.importorskip("cma", reason="pycma is not installed (locustjump[cma])")

from locustjump.errors import UserError  # noqa: E402
from locustjump.evo.cma import CMAES, CMAParams  # noqa: E402


def exactly(message):
    return "^" + re.escape(message) + "$"


def test_settings_ranges_and_their_boundaries():
    CMAParams(population=2, sigma0=1.0e6)
    CMAParams(sigma0=1e-300)
    for kwargs, message in [
        ({"population": 1}, "population must be an integer in [2, 1000000], got 1"),
        ({"sigma0": 0.0}, "sigma0 must be in (0, 1e+06], got 0.0"),
        ({"sigma0": 1.0e6 + 0.5}, "sigma0 must be in (0, 1e+06], got 1000000.5"),
        ({"sigma0": np.nan}, "sigma0 must be in (0, 1e+06], got nan"),
    ]:
        with pytest.raises(ValueError, match=exactly(message)):
            CMAParams(**kwargs)
    assert CMAParams().replace(population=7) == CMAParams(population=7)
    assert CMAES(3).params == CMAParams() and CMAES(3).seed == 0


def test_the_first_sample_is_sigma0_times_the_run_s_normal_draws(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    opt = CMAES(4, CMAParams(population=12, sigma0=0.3), seed=7)
    x = opt.ask()
    z = np.random.default_rng(7).standard_normal((12, 4))
    np.testing.assert_allclose(x, 0.3 * z, rtol=1e-3)  # pycma rounds its C
    d = opt.diagnostics()
    assert list(d) == ["sigma", "condition"] and d["sigma"] == 0.3
    assert d["condition"] == pytest.approx(1.0, abs=1e-3)
    opt.tell(-np.sum(x**2, axis=1))
    assert opt.ask().shape == (12, 4)
    assert list(tmp_path.iterdir()) == []  # pycma logs nothing to files


def test_pycma_says_nothing(capsys):
    opt = CMAES(3, CMAParams(population=4), seed=1)
    for _ in range(3):
        x = opt.ask()
        opt.tell(np.zeros(len(x)))  # flat fitness: pycma would warn and stop
    out, err = capsys.readouterr()
    assert (out, err) == ("", "")
    assert opt.stop() == {}


def test_the_state_is_the_seed_and_the_fitness_told():
    opt = CMAES(3, CMAParams(population=4), seed=2)
    told = []
    for _ in range(2):
        x = opt.ask()
        told.append(-np.sum(x**2, axis=1))
        opt.tell(told[-1])
    state = opt.state()
    assert int(state["seed"]) == 2 and state["fitness_history"].shape == (2, 4)
    np.testing.assert_array_equal(state["fitness_history"], told)
    back = CMAES.from_state(3, CMAParams(population=4), state, seed=2)
    np.testing.assert_array_equal(back.ask(), opt.ask())
    with pytest.raises(ValueError, match=exactly("state is of seed 2, not 3")):
        CMAES.from_state(3, CMAParams(population=4), state, seed=3)
    bad = {**state, "fitness_history": state["fitness_history"][:, :3]}
    with pytest.raises(
        ValueError, match=exactly("fitness_history has the wrong shape (2, 3)")
    ):
        CMAES.from_state(3, CMAParams(population=4), bad, seed=2)
    ints = {**state, "fitness_history": np.zeros((2, 4), dtype=np.int64)}
    again = CMAES.from_state(3, CMAParams(population=4), ints, seed=2)
    assert again.generation == 2


def test_without_pycma_the_error_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "cma", None)
    message = (
        "optimizer cma needs the cma library: pip install -e '.[cma]' in the clone"
    )
    with pytest.raises(UserError, match=exactly(message)):
        CMAES(3)


def test_cma_maximises_and_reports_only_numerical_stops(monkeypatch):
    opt = CMAES(3, CMAParams(population=8), seed=0)
    for _ in range(40):
        x = opt.ask()
        opt.tell(-np.sum((x - 0.3) ** 2, axis=1))
    np.testing.assert_allclose(opt.es.mean, 0.3, atol=0.01)  # measured: 4e-4
    reasons = {"tolfun": 1e-11, "maxiter": 3, "conditioncov": 1e14}
    monkeypatch.setattr(opt.es, "stop", lambda: reasons)
    assert opt.stop() == {"conditioncov": 1e14}

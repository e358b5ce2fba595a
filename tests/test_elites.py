"""One elite of an archive read as a best genome (:mod:`locustjump.rundir.elites`),
on a shipped repertoire (read only): which elite ``elite`` and ``cell`` name,
what it carries, and the words when it does not exist."""

from pathlib import Path

import numpy as np
import pytest

from helpers import exactly, user_error
from locustjump import rundir
from locustjump.errors import UserError
from locustjump.ranges import SettingTypeError, SettingValueError

ROOT = Path(__file__).resolve().parent.parent
REPERTOIRE = ROOT / "results" / "study" / "repertoire-kick-repertoire-s1"
ONE_NETWORK = ROOT / "results" / "study" / "debris-kick-s0"


@pytest.fixture(scope="module")
def archive():
    cfg, beh, _ = rundir.load_run(REPERTOIRE)
    return rundir.read_archive(REPERTOIRE, cfg, beh.controller.num_params)


def _expected(a, i):
    return (
        a.solution[i], float(a.objective[i]), int(a.generation[i]),
        tuple(int(c) for c in a.grid_index()[i]),
        tuple(float(m) for m in a.measures[i]),
    )  # fmt: skip


def _got(e):
    return e.genome, e.fitness, e.generation, e.cell, e.descriptors


def _same(got, expected):
    np.testing.assert_array_equal(got[0], expected[0])
    assert got[1:] == expected[1:]
    assert type(got[1]) is float and type(got[2]) is int


def test_neither_names_the_best_genome():
    cfg, beh, best = rundir.load_elite(REPERTOIRE)
    assert type(best) is rundir.BestGenome
    shipped = rundir.BestGenome.load(REPERTOIRE / rundir.BEST)
    np.testing.assert_array_equal(best.genome, shipped.genome)
    assert best.fitness == shipped.fitness
    assert cfg.behaviour == beh.name == "kick"


@pytest.mark.parametrize("rank", [0, 1, 3, 22])
def test_the_kth_elite_is_the_kth_best(archive, rank):
    cfg, _, e = rundir.load_elite(REPERTOIRE, elite=rank)
    i = archive.at_rank(rank)
    assert isinstance(e, rundir.Elite) and e.rank == rank
    _same(_got(e), _expected(archive, i))
    assert e.behaviour == "kick" and e.config_hash == cfg.hash()
    assert e.names == archive.names == ("apex_distance", "apex_rise")
    assert e.label == f"elite {rank} (cell {e.cell[0]},{e.cell[1]})"
    if rank == 0:
        assert e.fitness == rundir.load_run(REPERTOIRE)[2].fitness


def test_a_cell_names_its_elite_and_its_rank(archive):
    for rank in (0, 5, 22):
        i = archive.at_rank(rank)
        cell = tuple(int(c) for c in archive.grid_index()[i])
        e = rundir.load_elite(REPERTOIRE, cell=cell)[2]
        assert e.rank == rank and e.cell == cell
        _same(_got(e), _expected(archive, i))
    e = rundir.load_elite(REPERTOIRE, cell=[np.int64(c) for c in cell])[2]
    assert e.cell == cell and all(type(c) is int for c in e.cell)


def test_an_elite_that_does_not_exist_is_named(archive):
    assert user_error(rundir.load_elite, REPERTOIRE, elite=23) == (
        f"elite 23: elite 23 does not exist: the archive holds 23 (0 .. 22, best "
        f"first) "
        f"({REPERTOIRE / rundir.ARCHIVE})"
    )
    empty = tuple(int(c) for c in np.argwhere(np.isnan(archive.heat()))[0])
    assert user_error(rundir.load_elite, REPERTOIRE, cell=empty).startswith(
        f"cell {empty[0]},{empty[1]}: "
    )
    assert user_error(rundir.load_elite, REPERTOIRE, elite=0, cell=(0, 0)) == (
        "elite and cell: give one of them"
    )


def test_an_elite_of_a_run_without_archive_is_named():
    for kw, named in (({"elite": 0}, "elite 0"), ({"cell": (1, 2)}, "cell 1,2")):
        assert user_error(rundir.load_elite, ONE_NETWORK, **kw) == (
            f"{named}: {ONE_NETWORK} is a rcga run; only a quality-diversity run "
            "(map-elites, cma-me) keeps an archive of elites"
        )


def test_an_elite_and_a_cell_are_checked_before_the_run_is_read(tmp_path):
    nothing = tmp_path / "none"
    with pytest.raises(SettingValueError, match=exactly(
        "elite must be an integer in [0, 2**63-1], got -1"
    )):  # fmt: skip
        rundir.load_elite(nothing, elite=-1)
    with pytest.raises(SettingTypeError, match="^cell must be an integer"):
        rundir.load_elite(nothing, cell=(0, 1.5))
    with pytest.raises(UserError, match="^cell must be an integer in"):
        rundir.load_elite(nothing, cell=(0, -1))
    assert not nothing.exists()

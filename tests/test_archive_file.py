"""``archive.npz`` (rundir/archive.py): a quality-diversity run's elites
written in cell order and read back only when every array is what was
written and of this run's grid, each refusal one line naming the file."""

import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.evo import Archive, MapElitesParams, RCGAParams
from locustjump.rundir.archive import has_archive, read_archive, write_archive
from locustjump.rundir.config import TrainConfig

P = 144  # the kick network's genes
OTHER_RUN = "belongs to another run than {out}/config.toml"


def _cfg(**kw):
    return TrainConfig(behaviour="kick", optimizer=MapElitesParams(population=6,
                       cells=(3, 4), **kw))  # fmt: skip


def _archive(cfg):
    opt = cfg.optimizer
    rng = np.random.default_rng(0)
    return Archive(
        opt.descriptors, np.array([r[0] for r in opt.ranges]),
        np.array([r[1] for r in opt.ranges]), opt.cells, np.array([7, 0, 11]),
        rng.normal(size=(3, P)), np.array([0.5, 2.0, 1.5]),
        np.array([[3.0, 4.0], [-4.0, 0.1], [14.0, 4.9]]), np.array([3, 1, 2]),
    )  # fmt: skip


@pytest.fixture
def written(tmp_path):
    cfg = _cfg()
    write_archive(tmp_path / "archive.npz", cfg, _archive(cfg))
    return tmp_path, cfg


def test_the_elites_come_back_in_cell_order_bit_for_bit(written):
    out, cfg = written
    a, b = _archive(cfg).in_cell_order(), read_archive(out, cfg, P)
    assert b.index.tolist() == [0, 7, 11]
    assert (b.names, b.dims) == (a.names, a.dims) == (cfg.optimizer.descriptors, (3, 4))
    for k in ("lows", "highs", "index", "solution", "objective", "measures",
              "generation"):  # fmt: skip
        np.testing.assert_array_equal(getattr(b, k), getattr(a, k))
        assert getattr(b, k).dtype == getattr(a, k).dtype
    with np.load(out / "archive.npz", allow_pickle=False) as z:
        assert str(z["behaviour"]) == "kick" and str(z["config_hash"]) == cfg.hash()
        assert z["dims"].dtype == np.int64 and int(z["format"]) >= 1


def test_only_a_qd_run_keeps_one(tmp_path):
    assert has_archive(_cfg()) and not has_archive(TrainConfig(behaviour="kick"))
    rcga = TrainConfig(behaviour="kick", optimizer=RCGAParams(population=4))
    with pytest.raises(UserError) as err:
        read_archive(tmp_path, rcga, P)
    assert str(err.value) == (
        f"{tmp_path}: a rcga run keeps no archive of elites (train with "
        "optimizer map-elites or cma-me)"  # --optimizer on the command line
    )


def _rewritten(out, **changes):
    path = out / "archive.npz"
    with np.load(path, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    arrays.update(changes)
    np.savez(path, **arrays)
    return path


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"behaviour": np.array("getup")}, OTHER_RUN),
        ({"config_hash": np.array("0" * 16)}, OTHER_RUN),
        ({"names": np.array(["apex_rise", "apex_distance"])},
         "its grid is not the one config.toml names"),
        ({"lows": np.array([-5.0, 0.5])}, "its grid is not the one config.toml names"),
        ({"highs": np.array([15.0, 6.0])}, "its grid is not the one config.toml names"),
        ({"dims": np.array([4, 3])}, "its grid is not the one config.toml names"),
        ({"index": np.arange(13)}, "index must be at most 12 cells"),
        ({"index": np.zeros((3, 1), int)}, "index must be at most 12 cells"),
        ({"index": np.array([0.0, 7.0, 11.0])}, "index must be integers"),
        ({"generation": np.array([1.0, 2.0, 3.0])}, "generation must be integers"),
        ({"index": np.array([0, 7, 7])}, "two elites share a cell"),
        ({"index": np.array([0, 7, 12])}, "a cell index is outside the grid's 12"),
    ],
)  # fmt: skip
def test_an_archive_not_as_written_is_one_line_naming_it(written, change, message):
    out, cfg = written
    assert _refused(out, cfg, change) == message.format(out=out)


def _refused(out, cfg, change):
    """Why the archive with ``change`` is not read, after the file's name."""
    path = _rewritten(out, **change)
    with pytest.raises(UserError) as err:
        read_archive(out, cfg, P)
    head, _, why = str(err.value).partition(": ")
    assert head == str(path)
    return why


def test_its_arrays_must_have_the_runs_shapes(written):
    out, cfg = written
    _rewritten(out, solution=np.zeros((3, P + 1)))
    with pytest.raises(UserError, match="solution"):
        read_archive(out, cfg, P)
    _rewritten(out, solution=np.zeros((3, P)), measures=np.zeros((3, 3)))
    with pytest.raises(UserError, match="measures"):
        read_archive(out, cfg, P)


def test_an_empty_archive_reads_as_no_elites(tmp_path):
    cfg = _cfg()
    a = _archive(cfg)
    empty = Archive(a.names, a.lows, a.highs, a.dims, np.zeros(0, np.int64),
                    np.zeros((0, P)), np.zeros(0), np.zeros((0, 2)),
                    np.zeros(0, np.int64))  # fmt: skip
    write_archive(tmp_path / "archive.npz", cfg, empty)
    assert len(read_archive(tmp_path, cfg, P)) == 0


def test_a_full_grid_reads(tmp_path):
    cfg = _cfg()
    a = _archive(cfg)
    full = Archive(a.names, a.lows, a.highs, a.dims, np.arange(12),
                   np.ones((12, P)), np.arange(12.0), np.zeros((12, 2)),
                   np.ones(12, np.int64))  # fmt: skip
    write_archive(tmp_path / "archive.npz", cfg, full)
    assert len(read_archive(tmp_path, cfg, P)) == 12


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"solution": np.zeros((3, P + 1))}, f"solution has shape (3, {P + 1}), "
         f"expected (3, {P})"),
        ({"objective": np.zeros(4)}, "objective has shape (4,), expected (3,)"),
        ({"measures": np.zeros((3, 3))}, "measures has shape (3, 3), expected (3, 2)"),
        ({"lows": np.array([np.nan, 0.0])}, "lows holds NaN"),
        ({"format": np.array(999)}, "format 999, not one this locustjump reads"),
        ({"behaviour": np.array(["kick", "kick"])},
         "behaviour must be text, got a <U4 array of shape (2,)"),
        ({"config_hash": np.array(["a", "b"])},
         "config_hash must be text, got a <U1 array of shape (2,)"),
    ],
)  # fmt: skip
def test_each_array_refused_names_the_file(written, change, message):
    assert _refused(*written, change).startswith(message)


def test_a_one_descriptor_grid_may_be_stored_as_scalars(tmp_path):
    cfg = TrainConfig(behaviour="kick", optimizer=MapElitesParams(
        population=6, descriptors=("apex_rise",), cells=(5,)))  # fmt: skip
    opt = cfg.optimizer
    a = Archive(opt.descriptors, np.array([opt.ranges[0][0]]),
                np.array([opt.ranges[0][1]]), opt.cells, np.array([2]),
                np.ones((1, P)), np.ones(1), np.ones((1, 1)),
                np.ones(1, np.int64))  # fmt: skip
    write_archive(tmp_path / "archive.npz", cfg, a)
    _rewritten(tmp_path, names=np.array("apex_rise"), lows=np.array(opt.ranges[0][0]),
               highs=np.array(opt.ranges[0][1]), dims=np.array(5))  # fmt: skip
    assert read_archive(tmp_path, cfg, P).names == ("apex_rise",)


def _padded(out, cfg, over):
    """The archive rewritten with its ``behaviour`` padded so that its arrays
    declare ``over`` bytes more than the run's grid allows (less if < 0)."""
    budget = (1 << 16) + 12 * 8 * (P + 2 + 3)  # the 3 x 4 grid's, P genes
    with np.load(out / "archive.npz", allow_pickle=False) as z:
        others = sum(z[k].nbytes for k in z.files if k != "behaviour")
    chars = (budget + over - others) // 4  # text is 4 bytes a character
    _rewritten(out, behaviour=np.array("k" * chars))
    with np.load(out / "archive.npz", allow_pickle=False) as z:
        assert sum(z[k].nbytes for k in z.files) == budget + over
    return budget


def test_an_archive_larger_than_its_grid_holds_is_not_read(written):
    out, cfg = written
    budget = _padded(out, cfg, over=40)  # 40 bytes over: refused unread
    with pytest.raises(UserError) as err:
        read_archive(out, cfg, P)
    assert str(err.value) == (
        f"{out / 'archive.npz'}: its arrays declare {budget + 40:,} bytes, more "
        f"than such a file holds ({budget:,}; nothing inflated)"
    )
    _padded(out, cfg, over=-40)  # 40 bytes under: read (and found another run's)
    with pytest.raises(UserError, match="belongs to another run"):
        read_archive(out, cfg, P)


def test_cells_and_generations_stored_narrower_read_as_int64(written):
    out, cfg = written
    _rewritten(out, index=np.array([0, 7, 11], np.int32),
               generation=np.array([1, 3, 2], np.uint16))  # fmt: skip
    a = read_archive(out, cfg, P)
    assert a.index.dtype == a.generation.dtype == np.int64
    assert a.index.tolist() == [0, 7, 11] and a.generation.tolist() == [1, 3, 2]

"""The Python API refuses a value of the wrong kind when it is constructed,
naming the field: a ``TypeError`` for the wrong kind (a float where an integer
goes, a ``bool`` anywhere a number goes, a scene where terrains go), a
``ValueError`` for a value out of its range, as Python and NumPy do; both are
also a ``UserError``, which the command line prints on one line, exit 2. So a
configuration that could not be written back and read again never trains."""

import tomllib

import numpy as np
import pytest
import tomli_w

import locustjump as lj
from locustjump.errors import UserError
from locustjump.ranges import SettingTypeError, SettingValueError
from locustjump.rundir.config import TrainConfig
from locustjump.sim.controller import MLP
from locustjump.sim.engine.rollout import rollout
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks.starts import ready_state


@pytest.mark.parametrize(
    ("make", "field", "kind"),
    [
        (lambda: TrainConfig(generations=1.5), "generations", TypeError),
        (lambda: TrainConfig(generations=True), "generations", TypeError),
        (lambda: TrainConfig(generations=0), "generations", ValueError),
        (lambda: TrainConfig(seed=1.5), "seed", TypeError),
        (lambda: TrainConfig(seed=False), "seed", TypeError),
        (lambda: TrainConfig(seed=-1), "seed", ValueError),
        (lambda: TrainConfig(seed=2**63), "seed", ValueError),
        (lambda: TrainConfig(behaviour=3), "behaviour", TypeError),
        (lambda: TrainConfig(engine="fast"), "engine", ValueError),
        (lambda: TrainConfig(scene=Debris()), "scene", TypeError),
        (lambda: TrainConfig(optimizer={"population": 5}), "optimizer", TypeError),
        (lambda: TrainConfig(model=None), "model", TypeError),
        (lambda: lj.RCGAParams(population=6.5), "population", TypeError),
        (lambda: lj.RCGAParams(population=1), "population", ValueError),
        (lambda: lj.RCGAParams(elite=1.0), "elite", TypeError),
        (lambda: lj.RCGAParams(mutation_rate=True), "mutation_rate", TypeError),
        (lambda: lj.RCGAParams(mutation_rate=np.nan), "mutation_rate", ValueError),
        (lambda: lj.CMAParams(sigma0="1"), "sigma0", TypeError),
        (lambda: lj.RandomSearchParams(population=1), "population", ValueError),
        (lambda: Debris(length=True), "length", TypeError),
        (lambda: Debris(seed=1.0), "seed", TypeError),
        (lambda: Debris(spacing=5e-324), "spacing", ValueError),
        (lambda: Debris(wall_height=1e-9), "wall_height", ValueError),
        (lambda: Terrains(Debris(), count=2.0), "terrains", TypeError),
        (lambda: Terrains(Debris(seed=2**63 - 1), count=2), "terrains", ValueError),
        (lambda: lj.LocustParams(substeps=3.0), "substeps", TypeError),
        (lambda: lj.LocustParams(scale=True), "scale", TypeError),
        (lambda: lj.LocustParams(hip_pos=(0.0, 0.0)), "hip_pos", TypeError),
        (lambda: lj.LocustParams(solref=(0.0056, -1.0)), "solref", ValueError),
    ],
)
def test_a_wrong_value_is_refused_at_construction_naming_its_field(make, field, kind):
    with pytest.raises(kind) as e:
        make()
    assert isinstance(e.value, UserError)  # the command line: one line, exit 2
    assert str(e.value).startswith(f"{field} must be "), str(e.value)
    assert len(str(e.value).splitlines()) == 1


def test_rollout_refuses_a_fractional_step_count_before_it_simulates():
    p = lj.LocustParams()
    mlp = MLP()
    params = np.zeros((1, mlp.num_params))
    with pytest.raises(SettingTypeError, match="^n_steps must be an integer"):
        rollout(mlp, params, ready_state(p), 10.5, model_params=p)
    with pytest.raises(SettingValueError, match="^n_steps must be an integer"):
        rollout(mlp, params, ready_state(p), 0, model_params=p)
    res = rollout(mlp, params, ready_state(p), np.int64(2), model_params=p)
    assert res["qpos"].shape[1] == 3  # a NumPy integer: 2 steps and the start


def test_numbers_are_stored_as_the_field_holds_them_so_a_config_round_trips():
    cfg = TrainConfig(
        seed=np.int64(3),
        generations=np.int32(7),
        optimizer=lj.RCGAParams(population=np.int64(6), mutation_rate=0),
        model=lj.LocustParams(scale=10, hip_pos=[0.003, 0.006, -0.003]),
        scene=Terrains(Debris(length=5, seed=np.uint8(2)), count=np.int16(2)),
    )
    assert type(cfg.seed) is int and type(cfg.generations) is int
    assert type(cfg.optimizer.population) is int
    assert type(cfg.optimizer.mutation_rate) is float
    assert type(cfg.model.scale) is float
    assert cfg.model.hip_pos == (0.003, 0.006, -0.003)
    assert type(cfg.scene.count) is int and type(cfg.scene.scene.length) is float
    text = tomli_w.dumps(cfg.to_dict())  # NumPy numbers could not be written
    back = TrainConfig.from_dict(tomllib.loads(text), "config.toml")
    assert back == cfg and back.hash() == cfg.hash()


def test_a_config_that_cannot_be_written_back_never_trains(tmp_path):
    with pytest.raises(TypeError, match="^generations must be an integer"):
        lj.train(TrainConfig(generations=1.5), tmp_path / "run")
    assert not (tmp_path / "run").exists()

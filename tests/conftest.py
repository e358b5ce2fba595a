from pathlib import Path

# isort: off
import locustjump  # noqa: F401  (first: it picks MUJOCO_GL before mujoco loads)

# isort: on
import mujoco
import numpy as np
import pytest

from locustjump import model as lm


@pytest.fixture(scope="session")
def params() -> lm.LocustParams:
    return lm.LocustParams()


@pytest.fixture(scope="session")
def mjmodel(params) -> mujoco.MjModel:
    return lm.load_model(params)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1234)


#: the shipped reproduction (genomes evolved by `locustjump reproduce`)
SHIPPED = Path(__file__).resolve().parent.parent / "results" / "quick-seed0"


@pytest.fixture(scope="session")
def shipped() -> Path:
    if not (SHIPPED / "reproduce.toml").is_file():
        pytest.skip(f"{SHIPPED} not present")
    return SHIPPED

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

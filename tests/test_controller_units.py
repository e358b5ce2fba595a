"""The paper's network (``sim/controller.py``, :class:`MLP`), piece by piece:
its genome layout, its forward pass against a plain loop written from the
docstring, each output squashing, its compiled form, its checks. Every
evolved genome of the project is read through this layout."""

import math

import numpy as np
import pytest

from locustjump.sim.controller import MLP, Controller
from locustjump.sim.kernels import OUTPUTS

DEG10 = math.radians(10.0)


def _reference(net: MLP, genome: np.ndarray, x: np.ndarray) -> np.ndarray:
    """One network's outputs for one input, from the docstring's layout: W1
    (h, i), b1 (h,), W2 (o, h), b2 (o,), row-major; tanh hidden units."""
    i, h, o = net.n_in, net.n_hidden, net.n_out
    g = list(genome)
    w1 = [g[r * i : (r + 1) * i] for r in range(h)]
    b1 = g[h * i : h * i + h]
    k = h * i + h
    w2 = [g[k + r * h : k + (r + 1) * h] for r in range(o)]
    b2 = g[k + o * h :]
    assert len(b2) == o
    hidden = [
        math.tanh(sum(w1[r][c] * x[c] for c in range(i)) + b1[r]) for r in range(h)
    ]
    out = [sum(w2[r][c] * hidden[c] for c in range(h)) + b2[r] for r in range(o)]
    if net.output == "delta":
        return np.array([math.tanh(y) * DEG10 for y in out])
    if net.output == "sigmoid":
        return np.array([1.0 / (1.0 + math.exp(-y)) for y in out])
    return np.array(out)


def test_the_papers_network_is_9_10_4_with_144_genes():
    net = MLP()
    assert (net.n_in, net.n_hidden, net.n_out, net.output) == (9, 10, 4, "delta")
    assert net.num_params == 144 and net.memory_size == 0
    assert isinstance(net, Controller)


@pytest.mark.parametrize(
    ("sizes", "genes"), [((3, 5, 2), 5 * 4 + 2 * 6), ((1, 1, 1), 4), ((9, 6, 3), 81)]
)
def test_genes_are_both_layers_weights_and_biases(sizes, genes):
    assert MLP(*sizes).num_params == genes


def test_the_genome_layout_is_w1_b1_w2_b2_row_major():
    net = MLP(3, 5, 2)
    g = np.arange(2 * net.num_params, dtype=np.float64).reshape(2, -1)
    w = net.unflatten(g)
    p = net.num_params
    np.testing.assert_array_equal(w.w1[1], np.arange(p, p + 15).reshape(5, 3))
    np.testing.assert_array_equal(w.b1[1], np.arange(p + 15, p + 20))
    np.testing.assert_array_equal(w.w2[1], np.arange(p + 20, p + 30).reshape(2, 5))
    np.testing.assert_array_equal(w.b2[1], np.arange(p + 30, p + 32))
    assert [a.shape for a in w] == [(2, 5, 3), (2, 5), (2, 2, 5), (2, 2)]
    assert all(a.dtype == np.float64 for a in w)


def test_integer_genomes_are_read_as_floats():
    net = MLP(2, 2, 1)
    w = net.unflatten(np.ones((1, net.num_params), dtype=np.int64))
    assert all(a.dtype == np.float64 for a in w)


def test_prepare_unpacks_contiguous_copies_of_the_same_numbers():
    net = MLP()
    g = net.random_genomes(np.random.default_rng(0), 3)
    for a, b in zip(net.prepare(g), net.unflatten(g), strict=True):
        assert a.flags.c_contiguous
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    ("genome", "shape"),
    [
        (np.zeros(144), "(144,)"),
        (np.zeros((2, 143)), "(2, 143)"),
        (np.zeros((1, 1, 144)), "(1, 1, 144)"),
    ],
)
def test_a_genome_of_another_shape_is_named(genome, shape):
    with pytest.raises(ValueError) as got:
        MLP().unflatten(genome)
    assert str(got.value) == f"genome has shape {shape}, expected (n, 144)"


@pytest.mark.parametrize("output", ["delta", "sigmoid", "linear"])
def test_the_forward_pass_is_the_documented_network(output):
    net = MLP(9, 10, 4, output=output)
    rng = np.random.default_rng(7)
    genomes = net.random_genomes(rng, 5, scale=2.0)
    obs = rng.uniform(-1.5, 1.5, size=(5, 9))
    got = net.forward(genomes, obs)
    want = np.array([_reference(net, g, x) for g, x in zip(genomes, obs, strict=True)])
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)
    assert got.shape == (5, 4)
    np.testing.assert_array_equal(net.apply(net.prepare(genomes), obs), got)


def test_each_squashing_keeps_to_its_range():
    rng = np.random.default_rng(3)
    obs = rng.uniform(-1, 1, size=(50, 9))
    big = MLP().random_genomes(rng, 50, scale=20.0)
    delta = MLP(output="delta").forward(big, obs)
    assert np.abs(delta).max() <= DEG10 and np.abs(delta).max() > 0.9 * DEG10
    sig = MLP(output="sigmoid").forward(big, obs)
    assert sig.min() >= 0.0 and sig.max() <= 1.0
    lin = MLP(output="linear").forward(big, obs)
    assert np.abs(lin).max() > 1.0  # not squashed
    np.testing.assert_allclose(delta, np.tanh(lin) * DEG10, rtol=1e-14)
    np.testing.assert_allclose(sig, 1 / (1 + np.exp(-lin)), rtol=1e-14)


def test_act_is_the_forward_pass_and_keeps_no_memory():
    net = MLP()
    rng = np.random.default_rng(1)
    g = net.random_genomes(rng, 2)
    obs = rng.uniform(-1, 1, size=(2, 9))
    memory = np.zeros((2, 0))
    deltas, mem = net.act(net.prepare(g), memory, obs, np.zeros((2, 4)), 17)
    np.testing.assert_array_equal(deltas, net.forward(g, obs))
    assert mem is memory


@pytest.mark.parametrize("output", ["delta", "sigmoid", "linear"])
def test_the_compiled_form_is_the_weights_episode_last_and_the_output_code(output):
    net = MLP(9, 10, 4, output=output)
    prepared = net.prepare(net.random_genomes(np.random.default_rng(2), 3))
    kind, weights, code = net.kernel(prepared)
    assert kind == "mlp" and code == OUTPUTS[output]
    assert [w.shape for w in weights] == [(10, 9, 3), (10, 3), (4, 10, 3), (4, 3)]
    for w, p in zip(weights, prepared, strict=True):
        assert w.flags.c_contiguous
        np.testing.assert_array_equal(w, np.moveaxis(p, 0, -1))


def test_random_genomes_are_uniform_in_the_scale():
    net = MLP(3, 4, 2)
    g = net.random_genomes(np.random.default_rng(5), 400, scale=0.5)
    assert g.shape == (400, net.num_params)
    assert g.min() >= -0.5 and g.max() <= 0.5
    assert g.min() < -0.49 and g.max() > 0.49  # the whole range, both signs
    np.testing.assert_array_equal(
        g, np.random.default_rng(5).uniform(-0.5, 0.5, size=(400, net.num_params))
    )
    one = net.random_genomes(np.random.default_rng(5), 400)
    assert one.min() < -0.98 and one.max() > 0.98 and np.abs(one).max() <= 1.0


@pytest.mark.parametrize("sizes", [(0, 10, 4), (9, 0, 4), (9, 10, 0), (-1, 10, 4)])
def test_an_empty_layer_is_refused(sizes):
    with pytest.raises(ValueError) as got:
        MLP(*sizes)
    assert str(got.value) == "MLP layer sizes must be >= 1"
    MLP(*(max(s, 1) for s in sizes))  # one unit each is a network


def test_an_unknown_output_is_named():
    with pytest.raises(ValueError) as got:
        MLP(output="relu")
    assert str(got.value) == "unknown MLP output 'relu'"

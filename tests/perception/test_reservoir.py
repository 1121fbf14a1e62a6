"""Reservoir: SMC09 eq. 1 with the leak inside the tanh, batched runs, the online step."""

import numpy as np
import pytest

from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams, expand_leak


def _inputs(T=300, n=8, seed=0):
    rng = np.random.default_rng(seed)
    return rng.random((T, n))


def small(**kw):
    base = dict(n_inputs=8, n_neurons=60, seed=3)
    base.update(kw)
    return ReservoirParams(**base)


def test_spectral_radius_as_set():
    for rho in (0.5, 0.9, 0.99):
        r = Reservoir(small(spectral_radius=rho))
        assert abs(r.spectral_radius - rho) < 1e-9


def test_input_weights_are_ternary_with_paper_probabilities():
    r = Reservoir(ReservoirParams(n_inputs=200, n_neurons=100, seed=1))
    vals, counts = np.unique(r.W_in, return_counts=True)
    assert set(vals.tolist()) == {-2.0, 0.0, 2.0}
    frac = counts / counts.sum()
    assert abs(frac[0] - 0.075) < 0.01 and abs(frac[2] - 0.075) < 0.01
    r2 = Reservoir(ReservoirParams.icann09(n_inputs=200, n_neurons=100))
    assert set(np.unique(r2.W_in).tolist()) == {-0.2, 0.0, 0.2}
    assert abs(np.mean(r2.W_in != 0) - 0.30) < 0.02


def test_seeded_and_independent_streams():
    a, b = Reservoir(small()), Reservoir(small())
    assert np.array_equal(a.W_res, b.W_res) and np.array_equal(a.W_in, b.W_in)
    c = Reservoir(small(seed=4))
    assert not np.array_equal(a.W_res, c.W_res)
    # W_res does not depend on the number of inputs (its own random stream)
    d = Reservoir(small(n_inputs=3))
    assert np.array_equal(a.W_res, d.W_res)


def test_leak_one_is_standard_esn():
    r = Reservoir(small(leak=1.0), dtype="float64")
    U = _inputs()
    X = r.run(U)
    x = np.zeros(r.n_neurons)
    for t, u in enumerate(U):
        x = np.tanh(r.W_in @ u + r.W_res @ x)
        np.testing.assert_allclose(X[t], x, atol=1e-10)


def test_leak_inside_tanh():
    r = Reservoir(small(leak=(0.05, 0.15)), dtype="float64")
    U = _inputs(50)
    X = r.run(U)
    a = r.leak
    x = np.zeros(r.n_neurons)
    for t, u in enumerate(U):
        x = np.tanh((1 - a) * x + a * (r.W_in @ u + r.W_res @ x))
        np.testing.assert_allclose(X[t], x, atol=1e-12)
    assert np.all(a[:30] == 0.05) and np.all(a[30:] == 0.15)


def test_echo_state_property():
    r = Reservoir(small(leak=0.3, spectral_radius=0.9), dtype="float64")
    U = _inputs(1500)
    x0 = np.random.default_rng(9).uniform(-1, 1, r.n_neurons)
    Xa = r.run(U)
    Xb = r.run(U, x0=x0)
    assert np.abs(Xa[0] - Xb[0]).max() > 0.1
    assert np.abs(Xa[-1] - Xb[-1]).max() < 1e-6


@pytest.mark.parametrize("dtype,tol", [("float32", 1e-4), ("float64", 1e-10)])
def test_run_equals_repeated_step(dtype, tol):
    r = Reservoir(small(n_neurons=200), dtype=dtype)
    U = _inputs(400)
    X = r.run(U)
    r.reset()
    S = np.array([r.step(u).copy() for u in U])
    np.testing.assert_allclose(S, X, atol=tol)


def test_batched_equals_unbatched():
    r = Reservoir(small(), dtype="float64")
    U = np.stack([_inputs(200, seed=s) for s in range(3)])
    Xb = r.run(U)
    assert Xb.shape == (3, 200, 60)
    for b in range(3):
        np.testing.assert_allclose(Xb[b], r.run(U[b]), atol=1e-12)
    np.testing.assert_allclose(r.run(U[:2]), Xb[:2], atol=1e-12)  # two streams
    # leak sweep: one stream, B leak configurations over the same W_res
    leaks = np.array([[0.05, 0.15], [0.11, 0.14], [1.0, 1.0]])
    Xs = r.run(U[0], leak=leaks)
    assert Xs.shape == (3, 200, 60)
    for b, lk in enumerate(leaks):
        np.testing.assert_allclose(Xs[b], r.run(U[0], leak=tuple(lk)), atol=1e-12)


def test_expand_leak():
    np.testing.assert_array_equal(expand_leak(0.3, 4), [0.3] * 4)
    np.testing.assert_array_equal(expand_leak((0.1, 0.2), 5), [0.1, 0.1, 0.1, 0.2, 0.2])
    with pytest.raises(ValueError, match="leak"):
        expand_leak(0.0, 4)
    with pytest.raises(ValueError, match="leak"):
        expand_leak((0.1,) * 5, 4)
    # a full-length vector is used as is, as float64 (integer rates too)
    full = expand_leak([1, 1, 1], 3)
    assert full.dtype == np.float64 and np.array_equal(full, [1.0, 1.0, 1.0])
    # a matrix of rates, or none at all, is not a leak specification
    for bad in (np.full((2, 2), 0.1), ()):
        with pytest.raises(ValueError, match=r"^leak must be a number or a 1-D sequence"):
            expand_leak(bad, 4)


def test_bad_parameters_and_inputs():
    with pytest.raises(ValueError, match="spectral_radius"):
        ReservoirParams(spectral_radius=0.0)
    with pytest.raises(ValueError, match="spectral_radius"):
        ReservoirParams(spectral_radius=-1.0)
    with pytest.raises(ValueError, match="input_prob"):
        ReservoirParams(input_prob=0.7)
    r = Reservoir(small())
    with pytest.raises(ValueError, match="shape"):
        r.run(np.zeros((10, 3)))
    with pytest.raises(ValueError, match="NaN"):
        r.run(np.full((10, 8), np.nan))
    with pytest.raises(ValueError, match="shape"):
        r.step(np.zeros(7))
    with pytest.raises(ValueError, match=r"^u \(the sensor vector\) contains NaN or inf"):
        r.step(np.array([np.nan] + [0.0] * 7))
    # a value beyond float32's range is inf to a float32 reservoir: refused, not run
    with (pytest.warns(RuntimeWarning, match="overflow"),
          pytest.raises(ValueError, match=r"^u \(the sensor vector\) contains NaN or inf")):
        r.step(np.full(8, 1e39))
    assert np.all(np.isfinite(Reservoir(small(), dtype="float64").step(np.full(8, 1e39))))


def test_numpy_dtype_and_shape():
    r = Reservoir(small())
    X = r.run(np.random.default_rng(0).random((20, 8)))
    assert isinstance(X, np.ndarray) and X.dtype == np.float32 and X.shape == (20, 60)
    assert Reservoir(small(), dtype="float64").run(np.zeros((5, 8))).dtype == np.float64


def test_bad_backend_dtype_and_device():
    with pytest.raises(ValueError, match="dtype"):
        Reservoir(small(), dtype="float16")
    with pytest.raises(ValueError, match="device"):
        Reservoir(small(), device="tpu")
    with pytest.raises(ValueError, match="backend"):
        Reservoir(small()).run(np.zeros((5, 8)), backend="jax")


def test_torch_input_accepted():
    torch = pytest.importorskip("torch")
    r = Reservoir(small())
    U = torch.rand(20, 8)
    np.testing.assert_array_equal(r.run(U), r.run(U.numpy()))


def test_numpy_and_torch_backends_agree():
    pytest.importorskip("torch")
    r = Reservoir(small(), dtype="float64")
    U = _inputs(200)
    np.testing.assert_allclose(r.run(U), r.run(U, backend="torch"), atol=1e-12)
    leaks = np.array([[0.05, 0.15], [0.5, 0.9]])
    np.testing.assert_allclose(r.run(U, leak=leaks),
                               r.run(U, leak=leaks, backend="torch"), atol=1e-12)


def test_threads_do_not_change_the_states():
    r = Reservoir(small(), dtype="float64")
    U = _inputs(300)
    leaks = np.array([[0.05, 0.15], [0.11, 0.14], [0.3, 0.3], [1.0, 1.0]])
    one = r.run(U, leak=leaks, threads=1)
    two = r.run(U, leak=leaks, threads=2)
    np.testing.assert_allclose(one, two, atol=1e-12)
    np.testing.assert_allclose(r.run(U, threads=2), r.run(U), atol=1e-12)


def test_step_continues_eq1_from_a_given_state():
    # reset(x0) sets x(t); step(u) returns x(t+1) = tanh((1-a) x0 + a (W_in u + W_res x0))
    r = Reservoir(small(leak=(0.05, 0.15)), dtype="float64")
    rng = np.random.default_rng(1)
    x0, u = rng.uniform(-0.5, 0.5, r.n_neurons), rng.random(8)
    r.reset(x0)
    a = r.leak
    want = np.tanh((1 - a) * x0 + a * (r.W_in @ u + r.W_res @ x0))
    np.testing.assert_allclose(r.step(u), want, atol=1e-12)
    np.testing.assert_allclose(r.run(u[None], x0=x0)[0], want, atol=1e-12)
    r.reset()
    np.testing.assert_allclose(r.step(u), np.tanh(a * (r.W_in @ u)), atol=1e-12)
    with pytest.raises(ValueError, match="x0"):
        r.reset(np.zeros(r.n_neurons + 1))
    with pytest.raises(ValueError, match=r"^x0 contains 1 non-finite"):
        r.reset(np.r_[np.nan, np.zeros(r.n_neurons - 1)])


def test_the_paper_presets():
    # SMC09: 8 IR inputs, 600 neurons, leaks 0.05 / 0.15 by halves, rho 0.99, W_in +-2, p 0.075
    p = ReservoirParams.smc09()
    assert (p.n_inputs, p.n_neurons, p.spectral_radius, p.input_weight, p.input_prob) == (
        8, 600, 0.99, 2.0, 0.075)
    assert np.array_equal(expand_leak(p.leak, 4), [0.05, 0.05, 0.15, 0.15])
    # ICANN09: 17 inputs, 400 neurons, leak 0.6, rho 0.9, W_in +-0.2, p 0.15
    q = ReservoirParams.icann09()
    assert (q.n_inputs, q.n_neurons, q.spectral_radius, q.input_weight, q.input_prob) == (
        17, 400, 0.9, 0.2, 0.15)
    assert np.array_equal(expand_leak(q.leak, 3), [0.6, 0.6, 0.6])
    assert ReservoirParams.smc09(n_neurons=100, seed=4).n_neurons == 100  # overrides win


def test_repr_shows_the_leak_rates():
    assert "leak=0.05/0.15," in repr(Reservoir(small()))
    assert "leak=0.3," in repr(Reservoir(small(leak=0.3)))
    # at most the first four distinct rates
    assert "leak=0.1/0.2/0.3/0.4," in repr(Reservoir(small(leak=(0.1, 0.2, 0.3, 0.4, 0.5, 0.6))))


def test_non_finite_input_sequence_is_named():
    with pytest.raises(ValueError, match=r"\bU\b.*NaN"):
        Reservoir(small()).run(np.full((4, 8), np.inf))


def test_the_torch_backend_without_torch_says_how_to_install_it():
    try:
        import torch  # noqa: F401
    except ImportError:
        pass
    else:
        pytest.skip("torch is installed")
    with pytest.raises(ImportError, match=r"hippo\[torch\]"):
        Reservoir(small()).run(np.zeros((5, 8)), backend="torch")


def test_from_weights_keeps_the_weights_and_records_their_radius():
    r = Reservoir(small(leak=0.2), dtype="float64")
    s = Reservoir.from_weights(r.W_in, r.W_res, 0.2)
    assert s.dtype == "float32" and s.params.leak == 0.2
    assert s.params.spectral_radius == pytest.approx(0.99, rel=1e-9)  # max |eigenvalue|
    assert Reservoir.from_weights(r.W_in, r.W_res, 0.2, spectral_radius=5.0
                                  ).params.spectral_radius == 5.0  # recorded, not applied
    U = _inputs(20)
    np.testing.assert_allclose(s.run(U), r.run(U), atol=1e-5)
    one = Reservoir.from_weights(np.ones((1, 2)), np.full((1, 1), 0.5), 0.5, dtype="float64")
    assert one.params.leak == 0.5
    # the recorded parameters describe the weights: 2 inputs, 1 neuron
    assert (one.params.n_inputs, one.params.n_neurons) == (2, 1) == (one.n_inputs, one.n_neurons)
    # one neuron: x(1) = tanh(0.5 * 0 + 0.5 * (u1 + u2 + 0.5 * 0))
    assert one.run(np.array([[0.2, 0.4]]))[0, 0] == pytest.approx(np.tanh(0.3))


def test_from_weights_names_non_finite_weights():
    r = Reservoir(small(leak=0.2), dtype="float64")
    for name, (W_in, W_res) in {"W_in": (r.W_in + np.nan, r.W_res),
                                "W_res": (r.W_in, r.W_res + np.nan)}.items():
        with pytest.raises(ValueError, match=rf"^{name} contains \d+ non-finite"):
            Reservoir.from_weights(W_in, W_res, 0.2)


@pytest.mark.parametrize("dtype", ["float32", "float64"])
@pytest.mark.parametrize("leak", [None, np.array([[0.05, 0.15], [0.3, 0.3]])])
def test_a_run_continues_from_its_last_state_to_the_last_bits(dtype, leak):
    # run(U[k:], x0=run(U[:k])[-1]) continues eq. 1 from x(k): the whole run, in the
    # reservoir's own float type, to its last bits (a resumed robot is the robot that never
    # stopped). Not always bit for bit: BLAS computes W_in u for a block of ticks with kernels
    # chosen by the block's size (OpenBLAS's Haswell kernels on an AMD EPYC, 2026-11-26: 1 ulp
    # in 2 % of the float32 values for blocks of 2 or 50 ticks; bit for bit on the machines
    # before), and eq. 1 is contracting (spectral radius < 1), so a rounding does not grow
    r = Reservoir(small(), dtype=dtype)
    U = _inputs(120)
    whole = r.run(U, leak=leak)
    ulp = np.finfo(dtype).eps        # |x| <= 1 (tanh): an ulp is at most eps
    for k in (1, 2, 50):
        first = r.run(U[:k], leak=leak)
        rest = r.run(U[k:], x0=first[..., -1, :], leak=leak)
        np.testing.assert_allclose(np.concatenate([first, rest], axis=-2), whole, rtol=0,
                                   atol=4 * ulp)
    assert whole.dtype == np.dtype(dtype)
    # a continuation from another state is not the whole run: the check can fail
    first = r.run(U[:50], leak=leak)
    rest = r.run(U[50:], x0=0.9 * first[..., -1, :], leak=leak)
    assert np.abs(np.concatenate([first, rest], axis=-2) - whole).max() > 100 * ulp


def test_the_numpy_backend_is_the_default_on_the_cpu():
    r = Reservoir(small())
    U = _inputs(50)
    assert np.array_equal(r.run(U, backend="numpy"), r.run(U))


def test_a_bad_initial_state_of_a_run_is_named():
    # x0 is (N,) or (B, N) for B streams / leak configurations, and finite
    r = Reservoir(small())
    U = np.stack([_inputs(10, seed=s) for s in range(3)])
    for bad in (0.5, np.zeros(61), np.zeros((2, 60)), np.zeros((1, 1, 60))):
        with pytest.raises(ValueError, match=r"^x0 must have shape \(60,\) or \(3, 60\), got"):
            r.run(U, x0=bad)
    with pytest.raises(ValueError, match=r"^x0 contains 1 non-finite"):
        r.run(U[0], x0=np.r_[np.inf, np.zeros(59)])
    # one state for every stream, or one each
    x0 = np.random.default_rng(0).uniform(-0.5, 0.5, 60)
    np.testing.assert_array_equal(r.run(U, x0=x0), r.run(U, x0=np.tile(x0, (3, 1))))
    np.testing.assert_array_equal(r.run(U, x0=x0[None]), r.run(U, x0=x0))


def test_the_numpy_tick_loop_runs_on_threads_blas_threads(monkeypatch):
    # run(threads=n) sets the BLAS thread count for the tick loop and gives the caller's count
    # back; threads=None leaves it as it is
    from threadpoolctl import threadpool_info, threadpool_limits

    def blas():
        return {i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}

    r = Reservoir(small())
    U = _inputs(10)
    real_tanh, real_matmul, seen, drive = np.tanh, np.matmul, [], []

    def tanh(*args, **kw):
        seen.append(blas())
        return real_tanh(*args, **kw)

    def matmul(a, b, **kw):
        if not seen:  # before the first tick: the input drive W_in u(t), on one thread always
            drive.append(blas())
        return real_matmul(a, b, **kw)

    with threadpool_limits(2, user_api="blas"):
        if blas() != {2}:
            pytest.skip("no BLAS that threadpoolctl can set to 2 threads")
        monkeypatch.setattr(np, "tanh", tanh)
        monkeypatch.setattr(np, "matmul", matmul)
        for leak in (None, np.array([[0.05, 0.15], [0.3, 0.3]])):
            for kw, inside in (({"threads": 1}, {1}), ({"threads": None}, {2}), ({}, {1}),
                               ({"threads": 2}, {2})):
                seen.clear()
                drive.clear()
                r.run(U, leak=leak, **kw)  # the default is one thread
                assert seen == [inside] * 10 and blas() == {2}
                assert drive[:1] == [{1}]


def test_leak_rates_given_as_a_list_or_array_are_kept_as_a_tuple_of_floats():
    # the parameters are frozen and hashable: a list or 1-D array of rates becomes a tuple
    for given in ([0.05, 0.15], np.array([0.05, 0.15]), [1, 1]):
        p = ReservoirParams(n_neurons=4, leak=given)
        assert isinstance(p.leak, tuple) and all(type(v) is float for v in p.leak)
        assert p.leak == tuple(float(v) for v in given)
        hash(p)
    assert ReservoirParams(leak=0.3).leak == 0.3
    with pytest.raises(ValueError, match="leak"):  # a bool is not a rate
        ReservoirParams(n_neurons=4, leak=[True, 0.5])


def test_leak_specifications_name_their_faults():
    with pytest.raises(ValueError, match=r"^leak contains 1 non-finite"):
        expand_leak((0.1, np.nan), 4)
    for field in ("n_inputs", "n_neurons"):
        with pytest.raises(ValueError, match=rf"^ReservoirParams\.{field}\b"):
            ReservoirParams(**{field: 0})


def test_from_weights_refuses_weights_that_do_not_fit_and_records_the_leak():
    r = Reservoir(small(), dtype="float64")
    with pytest.raises(ValueError, match=r"^W_in \(N, n_u\) and W_res \(N, N\) do not fit"):
        Reservoir.from_weights(r.W_in[:, 0], r.W_res, 0.2)  # a vector, not (N, n_u)
    s = Reservoir.from_weights(r.W_in, r.W_res, (0.05, 0.15))
    assert s.params.leak == (0.05,) * 30 + (0.15,) * 30  # per neuron
    np.testing.assert_array_equal(s.leak, r.leak)


def test_streams_and_leak_configurations_that_do_not_broadcast_are_named():
    r = Reservoir(small())
    U = np.stack([_inputs(10, seed=s) for s in range(2)])
    leaks = np.array([[0.05, 0.15], [0.1, 0.1], [0.3, 0.3]])
    with pytest.raises(ValueError, match=r"^2 input streams and 3 leak configurations do not "
                                         r"broadcast"):
        r.run(U, leak=leaks)

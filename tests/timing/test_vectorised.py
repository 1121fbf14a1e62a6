"""The vectorised timing layer equals a plain, one-transition-at-a-time reference.

The transition cells learn and read out every transition of the winner with one array
operation; the spectral readout decodes all rows of a weight matrix at once. Here both are run
side by side with a plain form written row by row from the equations (HIREL eq. 1-3 and the
population readout of :class:`SpectralTiming`), on random winner sequences.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hippo.timing import SpectralTiming, TransitionCells, TransitionParams
from hippo.timing.nlms import learning_modulation, nlms_update
from hippo.timing.transition_params import TransitionReadout


def plain_code(timing: SpectralTiming, v: np.ndarray) -> float:
    """Weighted mean of log(mu) over the contiguous run above threshold around the peak."""
    i = int(np.argmax(v))
    vmax = float(v[i])
    if not vmax > 0.0:
        return math.nan
    th = timing.params.readout_fraction * vmax
    lo = i
    while lo > 0 and v[lo - 1] > th:
        lo -= 1
    hi = i
    while hi < v.size - 1 and v[hi + 1] > th:
        hi += 1
    w = v[lo:hi + 1] - th
    return float(np.sum(w * np.log(timing.mu[lo:hi + 1])) / np.sum(w))


def plain_readout(timing: SpectralTiming, v: np.ndarray) -> float:
    c = plain_code(timing, v)
    return math.nan if math.isnan(c) else float(np.interp(c, timing._cal_code, timing._cal_tau))


class PlainTransitionCells(TransitionCells):
    """The same cells, with learning, re-reading and readout done one transition at a time."""

    def _refresh(self, rows: np.ndarray) -> None:
        for r in rows:
            d = plain_readout(self.timing, self._w[r])
            self._delay[r] = d
            self._strength[r] = 0.0 if math.isnan(d) else float(
                np.sum(self._w[r] * self.timing.tuning(d)))

    def _learn(self, rows: np.ndarray, cs: np.ndarray, winner: int, dt: float) -> None:
        p = self.params.nlms
        changed = []
        for r in rows:
            b = self._keys[r][1]
            us = np.array([1.0 if b == winner else 0.0])
            eta = learning_modulation(us, self._m[[self._slot[b]]], p.sigma2)
            if eta[0] > 0.0:
                w, _ = nlms_update(self._w[[r]], cs, us, eta, p, dt)
                self._w[r] = w[0]
                changed.append(r)
        self._refresh(np.array(changed, dtype=int))

    def _read(self, a: int, activity: np.ndarray) -> dict:
        rows = self._out.get(a)
        if rows is None:
            self.elapsed = math.nan
            return {}
        self.elapsed = plain_readout(self.timing, activity)
        if math.isnan(self.elapsed):
            self.elapsed = math.inf
        out = {}
        lead = self.params.anticipation + self.params.latency
        for r in rows:
            d, s = float(self._delay[r]), float(self._strength[r])
            frac = self.elapsed / d if d > 0 else math.nan
            over = bool(s >= self.params.min_strength and frac >= 1.0 - lead / d)
            x = float(np.sum(self._w[r] * activity))
            out[self._keys[r]] = TransitionReadout(self._keys[r], x, s, d, frac, over)
        return out


def test_codes_of_many_rows_equal_the_plain_code():
    timing = SpectralTiming()
    rng = np.random.default_rng(3)
    taus = rng.uniform(0.0, 150.0, 40)
    rows = [timing.tuning(t) * rng.uniform(0.1, 3.0) for t in taus]
    rows += [rng.random(timing.n_cells) for _ in range(20)]          # ragged patterns
    rows += [np.zeros(timing.n_cells), -rng.random(timing.n_cells)]  # silent ones
    rows += [timing.tuning(5.0) + timing.tuning(40.0)]               # two bumps
    V = np.array(rows)
    got = timing._codes(V)
    want = np.array([plain_code(timing, v) for v in V])
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)
    assert np.isnan(got[-3]) and np.isnan(got[-2])
    for v, g in zip(V, timing._readouts(V)):
        w = plain_readout(timing, v)
        assert (math.isnan(g) and math.isnan(w)) or g == pytest.approx(w, rel=1e-12)


def test_elapsed_readout_is_the_readout_of_the_battery():
    timing = SpectralTiming()
    assert math.isnan(timing.elapsed_readout())
    for winner in [1] * 30 + [2] * 5 + [1] * 30:
        timing.step(winner, 0.2)
        assert timing.elapsed_readout() == timing.readout(timing.activity)
        assert timing.elapsed_readout() == pytest.approx(max(timing.tau, 0.2), rel=2e-3)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_vectorised_transition_cells_equal_the_plain_ones(seed: int):
    rng = np.random.default_rng(seed)
    fast_t, plain_t = SpectralTiming(), SpectralTiming()
    params = TransitionParams(latency=0.4)
    fast, plain = TransitionCells(fast_t, params), PlainTransitionCells(plain_t, params)
    winner, fired = 0, 0
    for _ in range(3000):
        if rng.random() < 0.08:  # dwell ~2.5 s, among 6 states (many shared successors)
            winner = int(rng.integers(6))
        rf = fast.step(fast_t.step(winner, 0.2), 0.2)
        rp = plain.step(plain_t.step(winner, 0.2), 0.2)
        assert rf.keys() == rp.keys()
        for k in rf:
            a, b = rf[k], rp[k]
            assert a.delay_over == b.delay_over
            fired += a.delay_over
            for name in ("prediction", "strength", "learned_delay", "elapsed_fraction"):
                x, y = getattr(a, name), getattr(b, name)
                assert (math.isnan(x) and math.isnan(y)) or x == pytest.approx(
                    y, rel=1e-10, abs=1e-12), name
        assert fast.elapsed == pytest.approx(plain.elapsed, rel=1e-12) or (
            math.isnan(fast.elapsed) and math.isnan(plain.elapsed))
    assert fast.transitions == plain.transitions and len(fast.transitions) > 20
    assert fired > 0  # the comparison covered the delay-over flag rising
    for k in fast.transitions:
        np.testing.assert_allclose(fast.weights(k), plain.weights(k), rtol=1e-10, atol=1e-13)
        assert fast.successors(k[0]) == plain.successors(k[0])


def _rows(timing: SpectralTiming, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    rows = [timing.tuning(t) * rng.uniform(0.1, 3.0) for t in rng.uniform(0.0, 150.0, 300)]
    rows += [rng.random(timing.n_cells) for _ in range(100)]            # ragged patterns
    rows += [rng.standard_normal(timing.n_cells) for _ in range(100)]   # signed ones
    rows += [np.zeros(timing.n_cells), -rng.random(timing.n_cells)]     # silent ones
    rows += [timing.tuning(5.0) + timing.tuning(40.0)]                  # two bumps
    return np.array(rows)


@pytest.mark.parametrize("fraction", [0.5, 0.0, 0.9])
def test_one_row_code_is_the_code_of_many_rows_bit_for_bit(fraction: float):
    """The per-tick readout of one row (_code, _readout) gives exactly the numbers of the
    all-rows form on a block of that one row (_codes, _readouts), silent rows included (nan).
    (Over a block of many rows the matrix product may round a row's sum differently: there
    the two agree to rounding.)"""
    from hippo.timing import SpectralParams
    timing = SpectralTiming(SpectralParams(readout_fraction=fraction))
    V = _rows(timing, 5)
    one = np.array([timing._code(v) for v in V])
    np.testing.assert_array_equal(one, [timing._codes(v[None])[0] for v in V])
    np.testing.assert_array_equal([timing._readout(v) for v in V],
                                  [timing._readouts(v[None])[0] for v in V])
    np.testing.assert_allclose(one, timing._codes(V), rtol=1e-13)
    assert np.isnan(one[-3]) and np.isnan(one[-2]) and not np.isnan(one[:-3]).any()


def test_one_row_refresh_is_the_array_refresh_bit_for_bit():
    """Re-reading one transition's delay and strength after it learned (the usual tick) gives
    the numbers of the array form over a block of one row."""
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    rng = np.random.default_rng(2)
    for winner in np.repeat(rng.integers(0, 5, 80), rng.integers(2, 60, 80)):
        cells.step(timing.step(int(winner), 0.2), 0.2)
    assert len(cells.transitions) > 10
    for r in range(len(cells.transitions)):
        w = cells._w[[r]]
        d = timing._readouts(w)
        s = 0.0 if np.isnan(d[0]) else np.einsum("rj,rj->r", w, timing._tuning(d))[0]
        cells._refresh(np.array([r]))
        assert cells._delay[r] == d[0] or (np.isnan(d[0]) and np.isnan(cells._delay[r]))
        assert cells._strength[r] == s


def test_sliding_mean_of_the_us_is_eq_3_on_every_tick():
    """m^US is left alone on ticks where eq. 3 would not change it (exactly one-hot at the
    winner): it equals eq. 3 applied on every tick, bit for bit."""
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    rng = np.random.default_rng(4)
    gamma = cells.params.nlms.gamma
    m, settled = np.zeros(16), 0
    for winner in np.repeat(rng.integers(0, 6, 60), rng.integers(1, 90, 60)):
        cells.step(timing.step(int(winner), 0.2), 0.2)
        m *= gamma
        m[cells._slot[int(winner)]] += 1.0 - gamma
        m[m < 1e-12] = 0.0
        np.testing.assert_array_equal(cells._m[:m.size], m[:cells._m.size])
        settled += cells._settled_at >= 0
    assert settled > 500  # the long stays did settle (and skipped the update)


def test_readout_flags_are_the_array_form_bit_for_bit():
    """The per-row scalars of the readout (elapsed fraction, delay over) equal the array
    formulas over all the winner's rows, on every tick of a random run (flags rising too)."""
    timing = SpectralTiming()
    cells = TransitionCells(timing, TransitionParams(latency=0.4))
    rng = np.random.default_rng(6)
    p, over = cells.params, 0
    for winner in np.repeat(rng.integers(0, 5, 150), rng.integers(2, 60, 150)):
        got = cells.step(timing.step(int(winner), 0.2), 0.2)
        rows = cells._out.get(int(winner))
        if rows is None:
            continue
        d, s = cells._delay[rows], cells._strength[rows]
        frac = cells.elapsed / d
        flag = (s >= p.min_strength) & (frac >= 1.0 - (p.anticipation + p.latency) / d)
        want = cells._w[rows] @ timing.activity
        np.testing.assert_array_equal([got[cells._keys[r]].elapsed_fraction for r in rows], frac)
        assert [got[cells._keys[r]].delay_over for r in rows] == flag.tolist()
        assert [got[cells._keys[r]].prediction for r in rows] == want.tolist()
        over += int(flag.sum())
    assert over > 10


def _nlms_with_leak_always(w, cs, us, eta, params, dt):
    """nlms_update as written before the no-US shortcut: the leak term always computed."""
    x = w @ cs
    norm = float(cs @ cs) + params.sigma1
    dw = params.alpha * eta[:, None] * ((us - x)[:, None] * cs / norm
                                        - params.leak * us[:, None] * w)
    return w + dt * dw, x


def test_nlms_without_us_skips_a_leak_that_changes_no_weight():
    """Between events (X^US = 0 on every row) the leak term is not computed: the weights are
    those of the full formula bit for bit, negative weights and underflowed CS cells included
    (where the skipped term is a negative zero)."""
    from hippo.timing.nlms import NLMSParams
    rng = np.random.default_rng(8)
    timing = SpectralTiming()
    for leak in (0.25, 0.0):
        p = NLMSParams(leak=leak)
        for k in range(1, 7):
            w = rng.standard_normal((k, timing.n_cells)) * 0.3
            w[:, ::7] = 0.0
            cs = timing.tuning(float(rng.uniform(0.0, 100.0)))  # far cells underflow to 0
            assert (cs == 0.0).any() and (w < 0).any()
            eta = rng.uniform(0.0, 0.5, k)
            for us in (np.zeros(k), (np.arange(k) == 0).astype(float)):
                got, x = nlms_update(w, cs, us, eta, p, 0.2)
                want, xw = _nlms_with_leak_always(w, cs, us, eta, p, 0.2)
                np.testing.assert_array_equal(got.view(np.int64), want.view(np.int64))
                np.testing.assert_array_equal(x, xw)


class ArrayLearnCells(TransitionCells):
    """The transition cells with eq. 2 on arrays (the form before the per-row floats)."""

    def _learn(self, rows: np.ndarray, cs: np.ndarray, winner: int, dt: float) -> None:
        p = self.params.nlms
        us = (self._target[rows] == winner).astype(float)
        eta = learning_modulation(us, self._m[self._target_slot[rows]], p.sigma2)
        learning = eta > 0.0
        if not np.count_nonzero(learning):
            return
        self._w[rows], _ = _nlms_with_leak_always(self._w[rows], cs, us, eta, p, dt)
        self._refresh(rows[learning])


@pytest.mark.parametrize("sigma2", [0.0, 0.01])
def test_learning_on_plain_floats_is_the_array_form_bit_for_bit(sigma2: float):
    """Eq. 2 row by row on floats (and the no-US shortcut) gives the weights, delays and
    strengths of the array form exactly, on every tick of a random run with shared successors
    (rows that learn next to rows that do not)."""
    from hippo.timing.nlms import NLMSParams
    params = TransitionParams(nlms=NLMSParams(sigma2=sigma2))
    ft, at = SpectralTiming(), SpectralTiming()
    fast, ref = TransitionCells(ft, params), ArrayLearnCells(at, params)
    rng = np.random.default_rng(9)
    partial = 0
    for winner in np.repeat(rng.integers(0, 6, 120), rng.integers(1, 40, 120)):
        fast.step(ft.step(int(winner), 0.2), 0.2)
        ref.step(at.step(int(winner), 0.2), 0.2)
        n = len(fast.transitions)
        rows = fast._out.get(int(winner), np.zeros(0, dtype=int))
        eta = fast._m[fast._target_slot[rows]] + sigma2
        partial += bool((eta > 0).any() and not (eta > 0).all())
        np.testing.assert_array_equal(fast._w[:n].view(np.int64), ref._w[:n].view(np.int64))
        np.testing.assert_array_equal(fast._delay[:n], ref._delay[:n])
        np.testing.assert_array_equal(fast._strength[:n], ref._strength[:n])
    assert len(fast.transitions) > 15
    assert partial > 50 or sigma2 > 0  # rows learning next to rows that do not


def test_refresh_keeps_the_battery_at_a_delay_only_while_the_delay_is_the_same():
    """The one-row refresh keeps X(T) per row; a row whose delay moved is read at its new
    delay (a kept X of the old delay would give another strength)."""
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    for winner in [0] * 20 + [1] * 30 + [0] * 20 + [1] * 3:
        cells.step(timing.step(winner, 0.2), 0.2)
    r = cells._index[(0, 1)]

    def want(w: np.ndarray) -> tuple[float, float]:
        d = timing._readouts(w[None])
        return d[0], np.einsum("rj,rj->r", w[None], timing._tuning(d))[0]

    for w in (timing.tuning(4.0) * 0.8, timing.tuning(4.0) * 0.4,   # same delay, kept X
              timing.tuning(9.0) * 0.8, timing.tuning(4.0) * 0.8):  # delay moved (and back)
        cells._w[r] = w
        cells._refresh(np.array([r]))
        d, s = want(w)
        assert cells._delay[r] == d and cells._strength[r] == s
        assert cells._at_delay[r][0] == d


def test_the_block_just_learned_is_read_that_tick_and_never_after():
    """The readout reads the rows learned this tick from the block the learning step made
    (the same numbers as a fresh gather) and drops it: no block survives into a later tick."""
    timing = SpectralTiming()
    cells = TransitionCells(timing)
    rng = np.random.default_rng(12)
    used = 0
    for winner in np.repeat(rng.integers(0, 5, 100), rng.integers(2, 30, 100)):
        orig = cells._learned
        assert orig is None
        got = cells.step(timing.step(int(winner), 0.2), 0.2)
        rows = cells._out.get(int(winner))
        assert cells._learned is None
        if rows is None:
            continue
        want = (cells._w[rows] @ timing.activity).tolist()
        assert [got[cells._keys[r]].prediction for r in rows] == want
        used += 1
    assert used > 1000

"""The place cells' parameters by hand (hippo.perception.place_cell_params): every refusal word
for word on its edge and one step past, the layers' checks named by the estimator's own field,
the SFA input width, the washout rule ceil(ln tol / ln(1 - a + a rho)) on hand-worked cases,
each field handed to the right layer, and the papers' presets field by field."""

from __future__ import annotations

import math
from dataclasses import FrozenInstanceError, dataclass

import numpy as np
import pytest

from hippo._checks import _hint_ok
from hippo.perception.ica_params import ICAParams
from hippo.perception.place_cell_params import ICANN09, SMC09, RCSFAICAParams
from hippo.perception.reservoir_params import ReservoirParams
from hippo.perception.sfa import SFAParams


def refusal(**kw: object) -> str:
    with pytest.raises(ValueError) as exc:
        RCSFAICAParams(**kw)
    return str(exc.value)


# ---------------------------------------------------------------------------- the defaults
def test_the_defaults_are_smc09s():
    p = RCSFAICAParams()
    assert p == SMC09
    assert (p.n_inputs, p.downsample, p.use_reservoir, p.n_reservoir) == (8, 1, True, 600)
    assert (p.leak, p.spectral_radius, p.input_weight, p.input_prob) == ((0.05, 0.15), 0.99,
                                                                         2.0, 0.075)
    assert (p.n_sfa, p.sfa_cutoff, p.sfa_expansion, p.slow_pool) == (4, 1e-8, "linear", 0.0)
    assert (p.n_ica, p.ica_algorithm, p.ica_restarts, p.ica_score) == (4, "symmetric", 10,
                                                                       "kurtosis")
    assert (p.ica_max_iter, p.ica_tol, p.washout, p.seed) == (1000, 1e-6, 0, 0)
    assert (p.dtype, p.device, p.input_range, p.out_of_range) == ("float32", "cpu", (0.0, 1.0),
                                                                  "error")
    assert p.min_fit_ticks == 100
    with pytest.raises(FrozenInstanceError):
        p.n_sfa = 5  # type: ignore[misc]


def test_icann09_field_by_field():
    p = ICANN09
    assert (p.n_inputs, p.downsample, p.n_reservoir, p.leak) == (17, 50, 400, 0.6)
    assert (p.spectral_radius, p.input_weight, p.input_prob) == (0.9, 0.2, 0.15)
    assert (p.n_sfa, p.n_ica) == (70, 70)
    # the rest as the defaults
    rest = {f: getattr(SMC09, f) for f in ("use_reservoir", "sfa_cutoff", "sfa_expansion",
                                           "slow_pool", "ica_algorithm", "ica_restarts",
                                           "ica_score", "ica_max_iter", "ica_tol", "washout",
                                           "seed", "dtype", "device", "input_range",
                                           "out_of_range", "min_fit_ticks")}
    assert all(getattr(p, f) == v for f, v in rest.items())


def test_leaks_and_ranges_given_as_lists_become_tuples():
    assert RCSFAICAParams(leak=[0.1, 0.2]).leak == (0.1, 0.2)
    assert RCSFAICAParams(leak=0.3).leak == 0.3
    p = RCSFAICAParams(input_range=[-1.0, 2.0])
    assert p.input_range == (-1.0, 2.0) and type(p.input_range) is tuple
    assert RCSFAICAParams(input_range=None).input_range is None


# ---------------------------------------------------------------------- the own refusals
@pytest.mark.parametrize(("field", "lo"), [("n_inputs", 1), ("downsample", 1), ("washout", 0),
                                           ("n_reservoir", 1), ("n_sfa", 1),
                                           ("min_fit_ticks", 3)])
def test_integer_fields_on_their_lower_bound_and_one_below(field, lo):
    # one leak rate, so that one neuron is enough
    kw = {"n_ica": 1, "leak": 0.1, **({"n_sfa": 4} if field != "n_sfa" else {})}
    assert getattr(RCSFAICAParams(**{**kw, field: lo}), field) == lo
    assert refusal(**{**kw, field: lo - 1}) == (f"{field} must be an integer >= {lo}, "
                                                f"got {lo - 1}")


def test_n_ica_from_1_to_n_sfa():
    assert RCSFAICAParams(n_ica=1).n_ica == 1
    assert refusal(n_ica=0) == "n_ica must be an integer >= 1, got 0"
    assert RCSFAICAParams(n_sfa=6, n_ica=6).n_ica == 6
    assert refusal(n_sfa=6, n_ica=7) == "n_ica=7 exceeds n_sfa=6"


def test_the_input_range_needs_low_below_high():
    assert RCSFAICAParams(input_range=(0.0, 1e-9)).input_range == (0.0, 1e-9)
    assert refusal(input_range=(1.0, 1.0)) == ("input_range must be (low, high) with low < high, "
                                               "got (1.0, 1.0)")
    assert refusal(input_range=(2.0, -1.0)) == ("input_range must be (low, high) with low < "
                                                "high, got (2.0, -1.0)")


def test_the_policy_dtype_device_and_slow_pool_are_checked():
    for policy in ("error", "warn", "clip"):
        assert RCSFAICAParams(out_of_range=policy).out_of_range == policy
    assert refusal(out_of_range="ignore") == ("out_of_range must be one of 'error', 'warn', "
                                              "'clip'; got 'ignore'")
    assert refusal(dtype="float16") == "dtype must be 'float32' or 'float64', got 'float16'"
    assert refusal(device="gpu") == "device must be 'cpu' or 'cuda[:N]', got 'gpu'"
    assert refusal(slow_pool=0.5) == ("slow_pool must be 0 (off) or a time constant >= 1 tick, "
                                      "got 0.5")
    assert RCSFAICAParams(slow_pool=1.0).slow_pool == 1.0
    # an integer or numpy time constant is kept as the float check_slow_pool makes of it
    for tau in (4, np.int64(4), np.float32(4.0)):
        kept = RCSFAICAParams(slow_pool=tau).slow_pool
        assert type(kept) is float and kept == 4.0
    assert refusal(n_sfa="4") == "RCSFAICAParams.n_sfa must be an integer, got '4' (str)"


# ------------------------------------------------------------ the layers' refusals, renamed
@pytest.mark.parametrize(("kw", "message"), [
    ({"spectral_radius": 0.0}, "spectral_radius: spectral_radius must be finite and > 0, got 0.0"),
    ({"leak": (0.1, 1.5)}, "leak: leak rates must lie in (0, 1], got 0.1..1.5"),
    ({"n_reservoir": 2, "leak": (0.1, 0.2, 0.3)},
     "leak: leak has 3 values but the reservoir has 2 neurons"),
    ({"input_weight": -1.0}, "input_weight: input_weight must be finite and >= 0, got -1.0"),
    ({"input_prob": 0.75}, "input_prob: input_prob must lie in [0.0, 0.5], got 0.75"),
    ({"sfa_cutoff": 1.0}, "sfa_cutoff: cutoff must lie in (0, 1), got 1.0"),
    ({"sfa_expansion": "cubic"},
     "sfa_expansion: expansion must be 'linear' or 'quadratic', got 'cubic'"),
    ({"ica_algorithm": "parallel"},
     "ica_algorithm: algorithm must be 'symmetric' or 'deflation', got 'parallel'"),
    ({"ica_max_iter": 0}, "ica_max_iter: max_iter must be >= 1, got 0"),
    ({"ica_tol": 0.0}, "ica_tol: tol must be > 0, got 0.0"),
    ({"ica_restarts": 0}, "ica_restarts: n_restarts must lie in [1, 1000] (each restart is a "
                          "whole FastICA fit), got 0"),
    ({"ica_score": "speed"},
     "ica_score: score must be one of ('kurtosis', 'sparseness', 'slowness'), got 'speed'"),
])
def test_a_layers_refusal_is_named_by_the_estimators_field(kw, message):
    assert refusal(**kw) == message


@dataclass(frozen=True)
class Odd(RCSFAICAParams):
    """A layer whose refusal names several of its fields, or none."""

    odd: str = ""

    def sfa_params(self) -> SFAParams:
        if self.odd:
            raise ValueError(self.odd)
        return super().sfa_params()


def test_a_refusal_naming_several_fields_or_none():
    with pytest.raises(ValueError) as exc:
        Odd(odd="expansion clashes with n_components and cutoff")
    # in the order of the table, with the estimator's names
    assert str(exc.value) == ("n_sfa / sfa_cutoff / sfa_expansion: expansion clashes with "
                              "n_components and cutoff")
    assert exc.value.__cause__ is None and exc.value.__suppress_context__
    with pytest.raises(ValueError) as exc:
        Odd(odd="broken")
    assert str(exc.value) == "RCSFAICAParams: broken"
    # whole words only: n_components_x names no field
    with pytest.raises(ValueError) as exc:
        Odd(odd="n_components_x and xcutoff")
    assert str(exc.value) == "RCSFAICAParams: n_components_x and xcutoff"


# -------------------------------------------------------------------- what the layers get
def test_each_field_reaches_its_layer():
    p = RCSFAICAParams(n_inputs=3, n_reservoir=7, leak=(0.2, 0.4), spectral_radius=0.8,
                       input_weight=0.5, input_prob=0.25, seed=11, n_sfa=5, sfa_cutoff=1e-6,
                       sfa_expansion="quadratic", n_ica=3, ica_algorithm="deflation",
                       ica_max_iter=77, ica_tol=1e-4, ica_restarts=2, ica_score="sparseness")
    assert p.reservoir_params() == ReservoirParams(n_inputs=3, n_neurons=7, spectral_radius=0.8,
                                                   leak=(0.2, 0.4), input_weight=0.5,
                                                   input_prob=0.25, seed=11)
    assert p.sfa_params() == SFAParams(n_components=5, cutoff=1e-6, expansion="quadratic")
    ica = p.ica_params()
    assert ica == ICAParams(n_components=3, algorithm="deflation", max_iter=77, tol=1e-4,
                            n_restarts=2, score="sparseness", seed=11)
    assert (ica.whiten, ica.workers) == ("auto", None)


def test_the_sfa_input_width():
    # [u; x]: 3 + 7; without a reservoir u alone; a slow pool doubles it
    assert RCSFAICAParams(n_inputs=3, n_reservoir=7).sfa_inputs == 10
    assert RCSFAICAParams(n_inputs=3, n_reservoir=7, use_reservoir=False).sfa_inputs == 3
    assert RCSFAICAParams(n_inputs=3, n_reservoir=7, slow_pool=4.0).sfa_inputs == 20
    assert RCSFAICAParams(n_inputs=3, use_reservoir=False, slow_pool=2.0).sfa_inputs == 6
    assert SMC09.sfa_inputs == 608


# ------------------------------------------------------------------------- the washout rule
def test_the_washout_for_hand_worked_reservoirs():
    # a = 1, rho = 0.5: r = 0.5; ln(1e-3) / ln(0.5) = 9.97 -> 10; ln(0.1) / ln(0.5) = 3.32 -> 4
    p = RCSFAICAParams(leak=1.0, spectral_radius=0.5)
    assert p.transient_updates() == 10
    assert p.transient_updates(0.1) == 4
    # the smallest leak counts: a = 0.25, rho 0.5: r = 0.875, 51.7 -> 52 (a = 0.5 would give
    # r = 0.75: 24.01 -> 25)
    assert RCSFAICAParams(leak=(0.5, 0.25), spectral_radius=0.5).transient_updates() == 52
    assert RCSFAICAParams(leak=0.5, spectral_radius=0.5).transient_updates() == 25
    # ICANN09 (the docstring's case): a 0.6, rho 0.9: r = 0.94, 111.6 -> 112, +2 for the filter
    assert ICANN09.transient_updates() == 114
    assert RCSFAICAParams(leak=0.6, spectral_radius=0.9).transient_updates() == 112
    # SMC09: a 0.05, rho 0.99: r = 0.9995, ln(1e-3) / ln(0.9995) = 13812.05 -> 13813
    assert SMC09.transient_updates() == 13813
    assert math.isclose(math.log(1e-3) / math.log(0.9995), 13812.05, abs_tol=0.01)


def test_the_filter_adds_two_updates_only_when_down_sampling():
    p = RCSFAICAParams(leak=1.0, spectral_radius=0.5)
    assert RCSFAICAParams(leak=1.0, spectral_radius=0.5, downsample=2).transient_updates() == 12
    assert p.transient_updates() == 10
    assert RCSFAICAParams(use_reservoir=False).transient_updates() == 0
    assert RCSFAICAParams(use_reservoir=False, downsample=2).transient_updates() == 2
    # without a reservoir a spectral radius of 1 is never read
    assert RCSFAICAParams(use_reservoir=False, spectral_radius=1.0).transient_updates() == 0


def test_the_washout_refuses_no_fading_memory_and_a_tolerance_outside_0_1():
    msg = ("spectral_radius={} leaves no fading memory (1 - a + a·ρ >= 1): the start is never "
           "forgotten")
    for rho in (1.0, 1.5):
        with pytest.raises(ValueError) as exc:
            RCSFAICAParams(spectral_radius=rho).transient_updates()
        assert str(exc.value) == msg.format(rho)
    # just below 1 still fades
    assert RCSFAICAParams(leak=1.0, spectral_radius=0.999).transient_updates() > 0
    for tol in (0.0, 1.0, -0.5, 2.0):
        with pytest.raises(ValueError) as exc:
            SMC09.transient_updates(tol)
        assert str(exc.value) == f"tol must lie in (0, 1), got {tol!r}"
    assert RCSFAICAParams(leak=1.0, spectral_radius=0.5).transient_updates(0.5) == 1


# ---------------------------------------------------- the range's values (hippo._checks)
@pytest.mark.parametrize("bad", [("a", "b"), (True, 2.0), (0.0, math.inf), (-math.inf, 1.0),
                                 (0.0, "1"), (None, 1.0)])
def test_the_input_range_holds_two_finite_real_numbers(bad):
    # each item against its own type: ("a", "b") would pass low < high ("a" < "b") and fail
    # later inside a fit with a TypeError
    assert refusal(input_range=bad) == (
        "RCSFAICAParams.input_range must be a tuple (a finite real number, a finite real number) "
        f"or None, got {bad!r} (tuple)")


def test_fixed_length_tuple_hints_check_each_item_against_its_own_type():
    assert _hint_ok((1, "x"), tuple[int, str])
    assert not _hint_ok(("x", 1), tuple[int, str])
    assert not _hint_ok((1, 2), tuple[int, str])
    assert not _hint_ok((1,), tuple[int, str]) and not _hint_ok((1, "x", 2), tuple[int, str])
    assert _hint_ok((np.float64(0.5), 2), tuple[float, float])
    assert not _hint_ok((0.5, np.nan), tuple[float, float])
    assert RCSFAICAParams(input_range=(np.float32(-1.0), 3)).input_range == (-1.0, 3)

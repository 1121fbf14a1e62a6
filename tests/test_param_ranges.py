"""The documented range of every numeric parameter of the neural modules, end by end.

Each row is ``(class, field, lo, hi, closed)``: the interval the docstring gives (``hi = inf``
for "> 0" / ">= 0"). Each end that belongs to the interval is accepted and each end that does
not is refused, as is a value just outside, with a ``ValueError`` that names the field
(issue 16: bad input is refused at the boundary and named). Mutation testing found that only
the field types were checked (tests/test_bad_inputs.py): a parameter whose range check named
the wrong field, or let its end in or out, went unnoticed.
"""

from __future__ import annotations

import math
import re

import pytest

from hippo.cognitive_map import DriveParams, PlannerParams
from hippo.cognitive_map.localise import LocaliserParams
from hippo.perception.ica_params import ICAParams
from hippo.perception.reservoir_params import ReservoirParams
from hippo.perception.sfa import SFAParams
from hippo.perception.states import StateLayerParams
from hippo.timing import NLMSParams, NonOccurrenceParams, SpectralParams, TransitionParams

INF = math.inf
RANGES = [
    (NLMSParams, "alpha", 0.0, INF, "neither"),
    (NLMSParams, "sigma1", 0.0, INF, "neither"),
    (NLMSParams, "sigma2", 0.0, INF, "left"),
    (NLMSParams, "gamma", 0.0, 1.0, "left"),
    (NLMSParams, "leak", 0.0, INF, "left"),
    (NonOccurrenceParams, "min_peak", 0.0, INF, "neither"),
    (NonOccurrenceParams, "rel_tolerance", 0.0, INF, "left"),
    (NonOccurrenceParams, "abs_tolerance", 0.0, INF, "left"),
    (NonOccurrenceParams, "fall_fraction", 0.0, 1.0, "neither"),
    (SpectralParams, "mu_min", 0.0, 120.0, "neither"),  # below mu_max (120 by default)
    (SpectralParams, "weber", 0.0, INF, "neither"),
    (SpectralParams, "min_width", 0.0, INF, "left"),
    (SpectralParams, "readout_fraction", 0.0, 1.0, "left"),
    (TransitionParams, "min_strength", 0.0, INF, "neither"),
    (TransitionParams, "anticipation", 0.0, INF, "left"),
    (TransitionParams, "latency", 0.0, INF, "left"),
    (SFAParams, "cutoff", 0.0, 1.0, "neither"),
    (ICAParams, "tol", 0.0, INF, "neither"),
    (ReservoirParams, "spectral_radius", 0.0, INF, "neither"),
    (ReservoirParams, "input_weight", 0.0, INF, "left"),
    (ReservoirParams, "input_prob", 0.0, 0.5, "both"),
    (StateLayerParams, "margin", 0.0, 1.0, "both"),
    (StateLayerParams, "hold_time", 0.0, INF, "left"),
    (StateLayerParams, "place_scale", 0.0, INF, "neither"),
    (StateLayerParams, "norm_tau", 0.0, INF, "neither"),
    (StateLayerParams, "smoothing", 0.0, INF, "left"),
    (StateLayerParams, "recruit_threshold", 0.0, 1.0, "both"),
    (StateLayerParams, "transient_time", 0.0, INF, "neither"),
    (StateLayerParams, "context_time", 0.0, INF, "left"),
    (DriveParams, "epsilon", 0.0, INF, "left"),
    (DriveParams, "learning_rate", 0.0, 1.0, "right"),
    (DriveParams, "extinction", 0.0, 1.0, "both"),
    (DriveParams, "min_weight", 0.0, 1.0, "both"),
    (DriveParams, "initial", 0.0, 1.0, "both"),
    (PlannerParams, "w", 0.0, 1.0, "neither"),
    (PlannerParams, "noise", 0.0, INF, "left"),
    (PlannerParams, "exploration_threshold", 0.0, 1.0, "both"),
    (PlannerParams, "replan_tolerance", 0.0, INF, "left"),
    (LocaliserParams, "delay_tolerance", 0.0, INF, "neither"),
    (LocaliserParams, "max_time", 0.0, INF, "neither"),
]

# integer sizes: (class, field, smallest allowed, other fields)
INT_MINIMA = [
    (SpectralParams, "n_cells", 4, {}),
    (SFAParams, "n_components", 1, {}),
    (ICAParams, "n_components", 1, {}),
    (ICAParams, "max_iter", 1, {}),
    (ICAParams, "n_restarts", 1, {}),
    (ICAParams, "workers", 1, {}),
    (ReservoirParams, "n_inputs", 1, {}),
    (ReservoirParams, "n_neurons", 1, {"leak": 0.1}),  # one neuron takes one leak rate
    (LocaliserParams, "n_known", 1, {}),
]

# string choices: (class, field, every allowed value)
CHOICES = [
    (SFAParams, "expansion", ("linear", "quadratic")),
    (ICAParams, "algorithm", ("symmetric", "deflation")),
    (ICAParams, "whiten", ("auto", True, False)),
    (StateLayerParams, "normalize", ("pooled", "unit", "fixed")),
    (PlannerParams, "method", ("states", "transitions")),
]


def _name(field: str) -> re.Pattern[str]:
    # the message names the field (PlannerParams.w is "propagation weight w")
    return re.compile(rf"\b{re.escape(field)}\b")


def _ids(rows) -> list[str]:
    return [f"{r[0].__name__}.{r[1]}" for r in rows]


@pytest.mark.parametrize(("cls", "field", "lo", "hi", "closed"), RANGES, ids=_ids(RANGES))
def test_each_end_of_a_range_is_in_or_out_as_documented(cls, field, lo, hi, closed):
    lo_in = closed in ("both", "left")
    hi_in = closed in ("both", "right")
    inside = (lo + hi) / 2 if hi < INF else lo + 1.0
    assert getattr(cls(**{field: inside}), field) == inside
    ends = [(lo, lo_in), (lo - 1e-3, False)]
    if hi < INF:
        ends += [(hi, hi_in), (hi + 1e-3, False)]
    else:
        ends += [(1e9, True), (INF, False)]
    for value, allowed in ends:
        if allowed:
            assert getattr(cls(**{field: value}), field) == value
        else:
            with pytest.raises(ValueError, match=_name(field)):
                cls(**{field: value})


@pytest.mark.parametrize(("cls", "field", "smallest", "other"), INT_MINIMA,
                         ids=_ids(INT_MINIMA))
def test_an_integer_size_below_its_minimum_is_refused_by_name(cls, field, smallest, other):
    assert getattr(cls(**other, **{field: smallest}), field) == smallest
    with pytest.raises(ValueError, match=_name(field)):
        cls(**other, **{field: smallest - 1})


@pytest.mark.parametrize(("cls", "field", "allowed"), CHOICES, ids=_ids(CHOICES))
def test_a_choice_outside_its_set_is_refused_by_name(cls, field, allowed):
    for value in allowed:
        assert getattr(cls(**{field: value}), field) == value
    with pytest.raises(ValueError, match=_name(field)):
        cls(**{field: "no-such-choice"})


def test_spectral_mu_max_must_exceed_mu_min():
    assert SpectralParams(mu_min=1.0, mu_max=1.5).mu_max == 1.5
    for mu_max in (1.0, 0.5):
        with pytest.raises(ValueError, match="mu_max"):
            SpectralParams(mu_min=1.0, mu_max=mu_max)

"""The bad-input table: every case must fail at the boundary with a clear error.

A case is ``(id, call, exception, pattern)``: ``call()`` must raise ``exception`` and its message
must match ``pattern`` (which names the argument, and mostly the value). The first part is
generated from every parameter dataclass (wrong types can never be right); the second lists the
semantic mistakes by hand: out-of-range values, data that cannot be learned from, inputs of the
wrong shape, and damaged files. The CLI mistakes live with the CLI tests.
"""

from __future__ import annotations

import dataclasses
import math
import re
import typing
import warnings

import numpy as np
import pytest

from hippo.brain import BrainParams
from hippo.cognitive_map import DriveParams, Drives, TransitionGraph
from hippo.cognitive_map.graph import Action
from hippo.cognitive_map.planner import Planner, PlannerParams, propagate
from hippo.io import CorruptFileError
from hippo.motor import MotorParams
from hippo.perception import RCSFAICA
from hippo.perception.ica import FastICA
from hippo.perception.ica_params import ICAParams
from hippo.perception.place_cell_inputs import InputRangeWarning
from hippo.perception.place_cells import RCSFAICAParams
from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
from hippo.perception.reservoir import Reservoir
from hippo.perception.reservoir_params import ReservoirParams
from hippo.perception.sfa import SFA, SFAParams
from hippo.perception.states import StateLayer, StateLayerParams
from hippo.sim import World, arenas
from hippo.sim.controllers import WallFollowerParams
from hippo.sim.record import record
from hippo.sim.robot import RobotParams, SensorModel
from hippo.tasks import Route, lead_from
from hippo.tasks.patrol import random_patrol
from hippo.timing import (
    NLMS,
    DelayRangeWarning,
    NLMSParams,
    NonOccurrence,
    NonOccurrenceParams,
    SpectralParams,
    SpectralTiming,
    TransitionCells,
    TransitionParams,
)

# ------------------------------------------------------------------ generated: wrong types
PARAM_CLASSES = [RCSFAICAParams, ReservoirParams, SFAParams, ICAParams, PrototypeParams,
                 StateLayerParams, SpectralParams, NLMSParams, TransitionParams,
                 NonOccurrenceParams, DriveParams, PlannerParams, BrainParams, MotorParams,
                 RobotParams, WallFollowerParams]


def _required(cls) -> dict[str, typing.Any]:
    """Values for the fields without defaults (SensorModel-like classes)."""
    out = {}
    for f in dataclasses.fields(cls):
        if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            out[f.name] = {"name": "x", "angles_deg": (0.0, 90.0)}.get(f.name, 1)
    return out


def _wrong_values(hint) -> list:
    """Values that a field of this type can never take."""
    args = typing.get_args(hint)
    origin = typing.get_origin(hint)
    allowed = set(args) if origin in (typing.Union, __import__("types").UnionType) else {hint}
    vals: list = []
    if allowed & {int} and not allowed & {float}:
        vals += [10.5, "3", True]
    if allowed & {float}:
        vals += [math.nan, math.inf, "0.5", True]
    if allowed == {str} or allowed == {str, type(None)}:
        vals += [3, 2.5]
    if allowed == {bool}:
        vals += ["yes", 2]
    if origin is typing.Literal:
        vals += ["no-such-choice", 1]
    if not vals:
        vals = [object()]  # a plain object fits no annotated field type
    return vals


def _generated_cases():
    cases = []
    for cls in PARAM_CLASSES:
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            hint = hints[f.name]
            if hint is typing.Any:
                continue
            for v in _wrong_values(hint):
                kw = {**_required(cls), f.name: v}
                cases.append(pytest.param(cls, kw, f.name,
                                          id=f"{cls.__name__}.{f.name}={v!r:.20}"))
    return cases


@pytest.mark.parametrize(("cls", "kwargs", "field"), _generated_cases())
def test_wrong_type_is_refused_at_construction(cls, kwargs, field):
    with pytest.raises(ValueError, match=re.escape(field)) as err:
        cls(**kwargs)
    assert repr(kwargs[field])[:10] in str(err.value) or field in str(err.value)


def test_the_generated_table_is_large():
    assert len(_generated_cases()) >= 150


# ---------------------------------------------------------------------- shared fixtures
_CACHE: dict[str, typing.Any] = {}


def _U() -> np.ndarray:
    if "U" not in _CACHE:
        _CACHE["U"] = record("two_rooms", 300, seed=5).sensors
    return _CACHE["U"]


def _model(**kw) -> RCSFAICA:
    key = f"model{sorted(kw.items())}"
    if key not in _CACHE:
        _CACHE[key] = RCSFAICA(n_reservoir=20, ica_restarts=1, **kw).fit(_U())
    return _CACHE[key]


def _world() -> World:
    return World(arenas.get("two_rooms"), seed=0)


def _graph() -> TransitionGraph:
    g = TransitionGraph()
    g.add_transition(0, 1, (0.0, 10.0), 2.0)
    g.add_transition(1, 2, "wait", 5.0)
    return g


def _drives() -> Drives:
    d = Drives()
    d.add("food")
    return d


def _agent_obs(**change):
    """A fresh agent, stepped once, and a valid next observation with ``change`` applied."""
    from hippo.agent import Agent, GroundTruthPlaceCells
    from hippo.types import Observation

    world = _world()
    agent = Agent(GroundTruthPlaceCells(np.array([[50.0, 50.0], [150.0, 50.0]])),
                  sensors=world.sensors, robot=world.robot, seed=0)
    obs = world.reset(0)
    for _ in range(2):  # the agent's clock is now at 0.2 s
        obs = world.step(agent.step(obs, world.truth))
    fields = {k: getattr(obs, k) for k in Observation.__slots__}
    fields.update(change)
    return agent, Observation(**fields), world.truth


def _agent_step(**change):
    agent, obs, truth = _agent_obs(**change)
    return agent.step(obs, truth)


def _agent_step_raw(obs):
    agent, _obs, truth = _agent_obs()
    return agent.step(obs, truth)


def _timing_at_event(previous_tau: float):
    t = SpectralTiming()
    cells = TransitionCells(t)
    cells.step(t.step(0, 0.2), 0.2)
    t.tau = previous_tau - 0.2
    return cells, t.step(1, 0.2)


def _damaged_model(tmp_path, key, change):
    path = _model().save(tmp_path / "m.npz")
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays[key] = change(arrays.get(key))
    if arrays[key] is None:  # the change deletes it
        del arrays[key]
    np.savez(tmp_path / "bad.npz", **arrays)
    return tmp_path / "bad.npz"


def _part(kind: str):
    """A small fitted SFA, FastICA or Reservoir (cached)."""
    if kind not in _CACHE:
        X = np.random.default_rng(0).laplace(size=(400, 5)) @ np.random.default_rng(1).normal(
            size=(5, 5))
        _CACHE[kind] = {"sfa": lambda: SFA(n_components=3).fit(X),
                        "ica": lambda: FastICA(n_components=3).fit(X),
                        "reservoir": lambda: Reservoir(ReservoirParams(n_neurons=10))}[kind]()
    return _CACHE[kind]


def _damaged_part(tmp_path, kind, key, change):
    """The saved part ``kind`` with array ``key`` changed (``change`` None: deleted)."""
    path = _part(kind).save(tmp_path / f"{kind}.npz")
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    if change is None:
        del arrays[key]
    else:
        arrays[key] = change(arrays.get(key))
    np.savez(tmp_path / "bad.npz", **arrays)
    return tmp_path / "bad.npz"


def _damaged_graphml(tmp_path, old, new):
    text = _graph().to_graphml(tmp_path / "g.graphml").read_text()
    assert old in text
    (tmp_path / "bad.graphml").write_text(text.replace(old, new, 1))
    return tmp_path / "bad.graphml"


V = ValueError
C = CorruptFileError
K = KeyError
R = RuntimeError

# (id, call(tmp_path), exception, pattern)
CASES: list[tuple[str, typing.Callable, type, str]] = [
    # --- RCSFAICA parameters
    ("rcsfaica n_reservoir 10.5", lambda p: RCSFAICA(n_reservoir=10.5), V, r"n_reservoir.*10\.5"),
    ("rcsfaica seed -1", lambda p: RCSFAICA(seed=-1), V, r"seed.*-1"),
    ("rcsfaica seed float", lambda p: RCSFAICA(seed=1.5), V, r"seed.*1\.5"),
    ("rcsfaica device tpu", lambda p: RCSFAICA(device="tpu"), V, r"device.*tpu"),
    ("rcsfaica dtype float16", lambda p: RCSFAICA(dtype="float16"), V, r"dtype.*float16"),
    # --- routes and leashes (hippo.tasks)
    ("route of one point repeated", lambda p: Route([(5, 5), (5, 5), (5, 5)]), V,
     r"^waypoints must not all be one point"),
    ("route progress nan", lambda p: Route([(0, 0), (10, 0), (10, 10)]).progress(np.nan, 0), V,
     r"^x must be finite"),
    ("route progress_near near nan",
     lambda p: Route([(0, 0), (10, 0), (10, 10)]).progress_near(1, 0, np.nan), V,
     r"^near must be finite"),
    ("route at text", lambda p: Route([(0, 0), (10, 0), (10, 10)]).at("3"), V,
     r"^s must be a real number"),
    ("lead_from start nan", lambda p: lead_from(arenas.get("maze"), (np.nan, 3.0), [(20, 20)]),
     V, r"^start x must be finite"),
    ("lead_from start outside", lambda p: lead_from(arenas.get("maze"), (-50, -50), [(20, 20)]),
     V, r"^start \(-50, -50\) lies outside arena 'maze-e1'"),
    ("lead_from waypoint inf",
     lambda p: lead_from(arenas.get("maze"), (20, 20), [(20, np.inf)]), V,
     r"^waypoints contains 1 non-finite"),
    ("random_patrol seed -1", lambda p: random_patrol("two-rooms", 2, -1), V, r"^seed.*-1"),
    ("rcsfaica fit ragged rows", lambda p: RCSFAICA(n_reservoir=20).fit([[0.1] * 8, [0.2] * 7]),
     V, r"^sensor sequence U must be an array of numbers, got list"),
    ("rcsfaica fit text", lambda p: RCSFAICA(n_reservoir=20).fit("0.1 0.2"), V,
     r"^sensor sequence U must have shape \(T, 8\)"),
    ("check_finite text", lambda p: SFA(n_components=1).fit([["a", "b"], ["c", "d"]]), V,
     r"^X must hold real numbers, got dtype <U1"),
    ("rcsfaica leak 0", lambda p: RCSFAICA(leak=0.0), V, r"leak"),
    ("rcsfaica leak 1.5", lambda p: RCSFAICA(leak=1.5), V, r"leak"),
    ("rcsfaica leak nan", lambda p: RCSFAICA(leak=(0.1, math.nan)), V, r"leak"),
    ("rcsfaica leak text", lambda p: RCSFAICA(leak="fast"), V, r"leak.*fast"),
    ("rcsfaica leak too many", lambda p: RCSFAICA(n_reservoir=3, leak=(.1, .2, .3, .4)), V,
     r"leak"),
    ("rcsfaica n_ica > n_sfa", lambda p: RCSFAICA(n_sfa=3, n_ica=4), V, r"n_ica=4.*n_sfa=3"),
    ("rcsfaica n_sfa 0", lambda p: RCSFAICA(n_sfa=0, n_ica=0), V, r"n_sfa|n_ica"),
    ("rcsfaica n_inputs 0", lambda p: RCSFAICA(n_inputs=0), V, r"n_inputs"),
    ("rcsfaica downsample 0", lambda p: RCSFAICA(downsample=0), V, r"downsample"),
    ("rcsfaica washout -1", lambda p: RCSFAICA(washout=-1), V, r"washout"),
    ("rcsfaica spectral radius 0", lambda p: RCSFAICA(spectral_radius=0.0), V,
     r"spectral_radius"),
    ("rcsfaica input_prob 0.7", lambda p: RCSFAICA(input_prob=0.7), V, r"input_prob"),
    ("rcsfaica sfa_cutoff 2", lambda p: RCSFAICA(sfa_cutoff=2.0), V, r"cutoff"),
    ("rcsfaica sfa_cutoff text", lambda p: RCSFAICA(sfa_cutoff="best"), V, r"cutoff"),
    ("rcsfaica expansion cubic", lambda p: RCSFAICA(sfa_expansion="cubic"), V, r"expansion"),
    ("rcsfaica ica algorithm", lambda p: RCSFAICA(ica_algorithm="parallel"), V, r"algorithm"),
    ("rcsfaica ica score", lambda p: RCSFAICA(ica_score="beauty"), V, r"score"),
    ("rcsfaica ica restarts 0", lambda p: RCSFAICA(ica_restarts=0), V, r"restarts"),
    ("rcsfaica input_range reversed", lambda p: RCSFAICA(input_range=(1.0, 0.0)), V,
     r"input_range"),
    ("rcsfaica out_of_range ignore", lambda p: RCSFAICA(out_of_range="ignore"), V,
     r"out_of_range.*ignore"),
    ("rcsfaica min_fit_ticks 1", lambda p: RCSFAICA(min_fit_ticks=1), V, r"min_fit_ticks"),
    ("rcsfaica unknown param", lambda p: RCSFAICA(n_neurons=10), TypeError, r"n_neurons"),
    # --- RCSFAICA fit data
    ("fit 5 ticks", lambda p: RCSFAICA(n_reservoir=20).fit(_U()[:5]), V,
     r"5 ticks.*min_fit_ticks"),
    ("fit U*100", lambda p: RCSFAICA(n_reservoir=20).fit(_U() * 100), V, r"outside input_range"),
    ("fit U-5", lambda p: RCSFAICA(n_reservoir=20).fit(_U() - 5), V, r"outside input_range"),
    ("fit stuck sensors", lambda p: RCSFAICA(n_reservoir=20).fit(np.ones((1500, 8))), V,
     r"constant"),
    ("fit stuck zeros", lambda p: RCSFAICA(n_reservoir=20).fit(np.zeros((1500, 8))), V,
     r"constant"),
    ("fit NaN", lambda p: RCSFAICA(n_reservoir=20).fit(np.where(_U() > .5, np.nan, _U())), V,
     r"non-finite"),
    ("fit inf", lambda p: RCSFAICA(n_reservoir=20).fit(np.where(_U() > .5, np.inf, _U())), V,
     r"non-finite"),
    ("fit 7 sensors", lambda p: RCSFAICA(n_reservoir=20).fit(_U()[:, :7]), V, r"\(T, 8\)"),
    ("fit 1-D", lambda p: RCSFAICA(n_reservoir=20).fit(_U()[:, 0]), V, r"\(T, 8\)"),
    ("fit 3-D", lambda p: RCSFAICA(n_reservoir=20).fit(_U()[None]), V, r"\(T, 8\)"),
    ("fit strings", lambda p: RCSFAICA(n_reservoir=20).fit(_U().astype(str)), V, r"real"),
    ("fit complex", lambda p: RCSFAICA(n_reservoir=20).fit(_U().astype(complex)), V, r"real"),
    # a cast to float used to drop the imaginary part silently (FastICA fitted the real part)
    ("ica fit complex", lambda p: FastICA(n_components=2).fit(_U()[:, :3] + 1j), V,
     r"^X must hold real numbers, got complex values"),
    ("route complex", lambda p: Route([(0, 0), (10, 0), (10, 10j)]), V,
     r"waypoints must hold real numbers, got complex"),
    ("fit bools", lambda p: RCSFAICA(n_reservoir=20).fit(_U() > .5), V, r"real"),
    ("fit None", lambda p: RCSFAICA(n_reservoir=20).fit(None), V, r"U must"),
    ("fit washout eats data", lambda p: RCSFAICA(n_reservoir=20, washout=250).fit(_U()), V,
     r"washout of 250"),
    # --- a fitted RCSFAICA
    ("step before fit", lambda p: RCSFAICA().step(np.zeros(8)), R, r"not fitted"),
    ("transform before fit", lambda p: RCSFAICA().transform(_U()), R, r"not fitted"),
    ("save before fit", lambda p: RCSFAICA().save(p / "m.npz"), R, r"not fitted"),
    ("step 1e6", lambda p: _model().step(_U()[0] * 1e6), V, r"outside input_range"),
    ("step -1", lambda p: _model().step(_U()[0] - 1), V, r"outside input_range"),
    ("step x50", lambda p: _model().step(np.full(8, 50.0)), V, r"outside input_range"),
    ("step 5 values", lambda p: _model().step(np.zeros(5)), V, r"shape \(8,\)"),
    ("step 2-D", lambda p: _model().step(_U()[:2]), V, r"shape \(8,\)"),
    ("step None", lambda p: _model().step(None), V, r"shape \(8,\)|real"),
    ("step text", lambda p: _model().step("abcdefgh"), V, r"real numbers"),
    ("step NaN", lambda p: _model().step(np.full(8, np.nan)), V, r"NaN"),
    ("step inf", lambda p: _model().step(np.r_[np.inf, np.zeros(7)]), V, r"NaN or inf"),
    ("transform x50", lambda p: _model().transform(_U() * 50), V, r"outside input_range"),
    ("transform 7 sensors", lambda p: _model().transform(_U()[:, :7]), V, r"\(T, 8\)"),
    # --- loading an RCSFAICA
    ("load missing", lambda p: RCSFAICA.load(p / "none.npz"), FileNotFoundError, r"none\.npz"),
    ("load folder", lambda p: RCSFAICA.load(p), C, r"not a file"),
    ("load output_std short", lambda p: RCSFAICA.load(_damaged_model(p, "output_std",
                                                                     lambda a: a[:-1])), C,
     r"output_std must have shape \(4,\)"),
    ("load output_std zero", lambda p: RCSFAICA.load(_damaged_model(p, "output_std",
                                                                    lambda a: a * 0)), C,
     r"output_std must be > 0"),
    ("load NaN sfa_W", lambda p: RCSFAICA.load(_damaged_model(
        p, "sfa_W", lambda a: np.where(a == a.flat[3], np.nan, a))), C, r"sfa_W contains"),
    ("load inf ica_mean", lambda p: RCSFAICA.load(_damaged_model(
        p, "ica_mean", lambda a: a + np.r_[np.inf, 0, 0, 0])), C, r"ica_mean contains"),
    ("load W_res rescaled", lambda p: RCSFAICA.load(_damaged_model(p, "W_res",
                                                                   lambda a: a * 3)), C,
     r"spectral radius"),
    ("load W_in transposed", lambda p: RCSFAICA.load(_damaged_model(p, "W_in",
                                                                    lambda a: a.T.copy())), C,
     r"W_in must have shape \(20, 8\)"),
    ("load leak changed", lambda p: RCSFAICA.load(_damaged_model(p, "leak",
                                                                 lambda a: a * 0 + 0.3)), C,
     r"leak does not match"),
    ("load sfa_scale negative", lambda p: RCSFAICA.load(_damaged_model(p, "sfa_scale",
                                                                       lambda a: -a)), C,
     r"sfa_scale must be > 0"),
    ("load format other", lambda p: RCSFAICA.load(_damaged_model(
        p, "format", lambda a: np.array("hippo.Other/1"))), C, r"not an RCSFAICA"),
    ("load params garbage", lambda p: RCSFAICA.load(_damaged_model(
        p, "params", lambda a: np.array("{not json"))), C, r"unreadable parameters"),
    ("load params list", lambda p: RCSFAICA.load(_damaged_model(
        p, "params", lambda a: np.array("[1, 2]"))), C, r"not a JSON object"),
    ("load params n_sfa text", lambda p: RCSFAICA.load(_damaged_model(
        p, "params", lambda a: np.array(str(a).replace('"n_sfa": 4', '"n_sfa": "4"')))), C,
     r"n_sfa"),
    ("load sfa_W int strings", lambda p: RCSFAICA.load(_damaged_model(
        p, "sfa_W", lambda a: a.astype(str))), C, r"sfa_W must hold real numbers"),
    ("load truncated", lambda p: RCSFAICA.load(
        (p / "t.npz", (p / "t.npz").write_bytes(_model().save(p / "m.npz").read_bytes()[:200]))[0]
    ), C, r"not a readable \.npz"),
    ("load text file", lambda p: RCSFAICA.load(
        (p / "t.npz", (p / "t.npz").write_text("hello"))[0]), C, r"not a readable \.npz"),
    ("load extra array", lambda p: RCSFAICA.load(_damaged_model(
        p, "stray", lambda a: np.ones(2))), C, r"unknown array\(s\) stray"),
    ("load sfa_W missing", lambda p: RCSFAICA.load(_damaged_model(p, "sfa_W", lambda a: None)),
     C, r"SFA state lacks array\(s\) sfa_W"),
    ("load ica_rotation skewed", lambda p: RCSFAICA.load(_damaged_model(
        p, "ica_rotation", lambda a: a + 0.1)), C, r"ica_rotation is not orthonormal"),
    # --- the parts' own files (SFA, FastICA, Reservoir)
    ("sfa save before fit", lambda p: SFA().save(p / "s.npz"), R, r"SFA is not fitted"),
    ("sfa to_arrays before fit", lambda p: SFA().to_arrays(), R, r"SFA is not fitted"),
    ("ica save before fit", lambda p: FastICA().save(p / "i.npz"), R, r"FastICA is not fitted"),
    ("sfa from_arrays empty", lambda p: SFA.from_arrays(SFAParams(), {}), V,
     r"SFA state lacks array\(s\) mean, scale, W, slowness"),
    ("ica from_arrays sfa state", lambda p: FastICA.from_arrays(ICAParams(), _part(
        "sfa").to_arrays()), V, r"FastICA state lacks array\(s\) whitening, rotation"),
    ("sfa from_arrays width", lambda p: SFA.from_arrays(SFAParams(n_components=3), _part(
        "sfa").to_arrays(), n_features_in=4), V, r"mean must have shape \(4,\)"),
    ("sfa load missing", lambda p: SFA.load(p / "none.npz"), FileNotFoundError, r"none\.npz"),
    ("sfa load ica file", lambda p: SFA.load(_part("ica").save(p / "i.npz")), C,
     r"not a saved SFA \(format 'hippo\.perception\.FastICA/1'"),
    ("ica load sfa file", lambda p: FastICA.load(_part("sfa").save(p / "s.npz")), C,
     r"not a saved FastICA \(format 'hippo\.perception\.SFA/1'"),
    ("reservoir load model file", lambda p: Reservoir.load(_model().save(p / "m.npz")), C,
     r"not a saved Reservoir"),
    ("sfa load version 2", lambda p: SFA.load(_damaged_part(
        p, "sfa", "format", lambda a: np.array("hippo.perception.SFA/2"))), C,
     r"format version 'hippo\.perception\.SFA/2'"),
    ("sfa load W missing", lambda p: SFA.load(_damaged_part(p, "sfa", "W", None)), C,
     r"bad\.npz: the SFA state lacks array\(s\) W"),
    ("sfa load extra array", lambda p: SFA.load(_damaged_part(
        p, "sfa", "stray", lambda a: np.ones(3))), C, r"unknown array\(s\) stray"),
    ("sfa load W short", lambda p: SFA.load(_damaged_part(p, "sfa", "W", lambda a: a[:-1])), C,
     r"W must have shape \(5, 3\)"),
    ("sfa load NaN W", lambda p: SFA.load(_damaged_part(
        p, "sfa", "W", lambda a: np.where(a == a.flat[2], np.nan, a))), C, r"W contains 1"),
    ("sfa load scale 0", lambda p: SFA.load(_damaged_part(p, "sfa", "scale", lambda a: 0 * a)),
     C, r"scale must be > 0"),
    ("sfa load params unknown", lambda p: SFA.load(_damaged_part(
        p, "sfa", "params", lambda a: np.array('{"n_components": 3, "speed": 2}'))), C,
     r"unknown SFAParams parameter\(s\) speed"),
    ("ica load rotation skewed", lambda p: FastICA.load(_damaged_part(
        p, "ica", "rotation", lambda a: a + 0.1)), C, r"rotation is not orthonormal"),
    ("ica load inf mean", lambda p: FastICA.load(_damaged_part(
        p, "ica", "mean", lambda a: a + np.r_[np.inf, 0, 0, 0, 0])), C, r"mean contains 1"),
    ("reservoir load leak changed", lambda p: Reservoir.load(_damaged_part(
        p, "reservoir", "leak", lambda a: a * 0 + 0.5)), C, r"leak does not match"),
    ("reservoir load W_res rescaled", lambda p: Reservoir.load(_damaged_part(
        p, "reservoir", "W_res", lambda a: 2 * a)), C, r"W_res has spectral radius"),
    ("reservoir load W_in 3-D", lambda p: Reservoir.load(_damaged_part(
        p, "reservoir", "W_in", lambda a: a[None])), C, r"W_in must have shape \(10, 8\)"),
    # --- Reservoir, SFA, ICA
    ("reservoir n_neurons 0", lambda p: ReservoirParams(n_neurons=0), V, r"n_neurons"),
    ("reservoir radius -1", lambda p: ReservoirParams(spectral_radius=-1.0), V,
     r"spectral_radius"),
    ("reservoir input_weight -2", lambda p: ReservoirParams(input_weight=-2.0), V,
     r"input_weight"),
    ("reservoir device", lambda p: Reservoir(ReservoirParams(n_neurons=5), device="gpu"), V,
     r"device.*gpu"),
    ("reservoir dtype", lambda p: Reservoir(ReservoirParams(n_neurons=5), dtype="int8"), V,
     r"dtype.*int8"),
    ("reservoir weights misfit", lambda p: Reservoir.from_weights(np.ones((3, 2)), np.ones((4, 4)),
                                                                  0.5), V, r"W_in.*W_res"),
    ("reservoir weights NaN", lambda p: Reservoir.from_weights(np.full((3, 2), np.nan),
                                                               np.eye(3), 0.5), V, r"W_in"),
    ("reservoir run backend", lambda p: Reservoir(ReservoirParams(n_neurons=5)).run(
        np.zeros((3, 8)), backend="cuda"), V, r"backend"),
    ("sfa n 0", lambda p: SFAParams(n_components=0), V, r"n_components"),
    ("sfa cutoff 0", lambda p: SFAParams(cutoff=0.0), V, r"cutoff"),
    ("sfa fit 1-D", lambda p: SFA().fit(np.zeros(10)), V, r"2-D|shape"),
    ("sfa fit NaN", lambda p: SFA().fit(np.full((50, 6), np.nan)), V, r"non-finite"),
    ("sfa transform unfitted", lambda p: SFA().transform(np.zeros((5, 3))), R, r"not fitted"),
    ("ica n 0", lambda p: ICAParams(n_components=0), V, r"n_components"),
    ("ica tol 0", lambda p: ICAParams(tol=0.0), V, r"tol"),
    ("ica whiten yes", lambda p: ICAParams(whiten="yes"), V, r"whiten"),
    ("ica workers 0", lambda p: ICAParams(workers=0), V, r"workers"),
    ("ica k > d", lambda p: FastICA(n_components=5).fit(np.random.default_rng(0).normal(
        size=(50, 3))), V, r"n_ica=5 exceeds"),
    ("ica fit 1-D", lambda p: FastICA().fit(np.zeros(10)), V, r"2-D"),
    ("ica transform unfitted", lambda p: FastICA().transform(np.zeros((5, 3))), R,
     r"not fitted"),
    # --- prototypes
    ("prototypes step 5 values", lambda p: PlacePrototypes(PrototypeParams(n_prototypes=3)).fit(
        np.random.default_rng(0).normal(size=(40, 4))).step(np.zeros(5)), V, r"shape \(4,\)"),
    ("prototypes transform 3 cols", lambda p: PlacePrototypes(PrototypeParams(n_prototypes=3)).fit(
        np.random.default_rng(0).normal(size=(40, 4))).transform(np.zeros((2, 3))), V,
     r"\(T, 4\)"),
    ("prototypes unfitted", lambda p: PlacePrototypes().step(np.zeros(4)), R, r"not fitted"),
    ("prototypes too few", lambda p: PlacePrototypes(PrototypeParams(n_prototypes=8)).fit(
        np.zeros((3, 2))), V, r"n_prototypes=8"),
    ("prototypes fit NaN", lambda p: PlacePrototypes().fit(np.full((40, 2), np.nan)), V,
     r"non-finite"),
    ("prototypes threshold 1", lambda p: PrototypeParams(recruit_threshold=1.0), V,
     r"recruit_threshold"),
    ("prototypes max < n", lambda p: PrototypeParams(n_prototypes=5, max_prototypes=4), V,
     r"max_prototypes"),
    # --- state layer
    ("states dt 0", lambda p: StateLayer().step(np.zeros(3), dt=0.0), V, r"dt"),
    ("states dt nan", lambda p: StateLayer().step(np.zeros(3), dt=math.nan), V, r"dt"),
    ("states place NaN", lambda p: StateLayer().step(np.full(3, np.nan), dt=0.2), V,
     r"non-finite|NaN"),
    ("states place 2-D", lambda p: StateLayer().step(np.zeros((2, 3)), dt=0.2), V, r"place"),
    ("states margin -1", lambda p: StateLayerParams(margin=-1.0), V, r"margin"),
    ("states hold -1", lambda p: StateLayerParams(hold_time=-1.0), V, r"hold_time"),
    ("states normalize", lambda p: StateLayerParams(normalize="zscore"), V, r"normalize"),
    ("states events", lambda p: StateLayerParams(events=("smell",)), V, r"smell"),
    # --- timing
    ("spectral winner -1", lambda p: SpectralTiming().step(-1, 0.2), V, r"winner.*-1"),
    ("spectral winner 1.5", lambda p: SpectralTiming().step(1.5, 0.2), V, r"winner.*1\.5"),
    ("spectral winner text", lambda p: SpectralTiming().step("a", 0.2), V, r"winner"),
    ("spectral dt -0.2", lambda p: SpectralTiming().step(0, -0.2), V, r"dt"),
    ("spectral dt 0", lambda p: SpectralTiming().step(0, 0.0), V, r"dt"),
    ("spectral dt nan", lambda p: SpectralTiming().step(0, math.nan), V, r"dt"),
    ("spectral tau -1", lambda p: SpectralTiming().tuning(-1.0), V, r"tau"),
    ("spectral readout shape", lambda p: SpectralTiming().readout(np.ones(3)), V, r"pattern"),
    ("spectral n_cells 3", lambda p: SpectralParams(n_cells=3), V, r"n_cells"),
    ("spectral mu order", lambda p: SpectralParams(mu_min=5.0, mu_max=1.0), V, r"mu_max"),
    ("spectral weber 0", lambda p: SpectralParams(weber=0.0), V, r"weber"),
    ("transitions battery text", lambda p: TransitionCells(SpectralTiming()).step("b", 0.2), V,
     r"battery"),
    ("transitions timing wrong", lambda p: TransitionCells("t"), V, r"timing"),
    ("transitions dt 0", lambda p: TransitionCells(SpectralTiming()).step(
        SpectralTiming().step(0, 0.2), 0.0), V, r"dt"),
    ("transitions min_strength 0", lambda p: TransitionParams(min_strength=0.0), V,
     r"min_strength"),
    ("transitions nlms type", lambda p: TransitionParams(nlms={"alpha": 1}), V, r"nlms"),
    ("nlms sizes 0", lambda p: NLMS(0, 3), V, r"n_out"),
    ("nlms sizes float", lambda p: NLMS(2.5, 3), V, r"n_out"),
    ("nlms cs shape", lambda p: NLMS(2, 3).step(np.zeros(4), np.zeros(2), 0.2), V, r"cs"),
    ("nlms us shape", lambda p: NLMS(2, 3).step(np.zeros(3), np.zeros(3), 0.2), V, r"us"),
    ("nlms cs NaN", lambda p: NLMS(2, 3).step(np.full(3, np.nan), np.zeros(2), 0.2), V, r"cs"),
    ("nlms dt -1", lambda p: NLMS(2, 3).step(np.zeros(3), np.zeros(2), -1.0), V, r"dt"),
    ("nlms gamma 1", lambda p: NLMSParams(gamma=1.0), V, r"gamma"),
    ("nlms alpha 0", lambda p: NLMSParams(alpha=0.0), V, r"alpha"),
    ("nonocc predictions list", lambda p: NonOccurrence().step([0.5], 0.2), V, r"predictions"),
    ("nonocc prediction NaN", lambda p: NonOccurrence().step({(0, 1): math.nan}, 0.2), V,
     r"prediction of \(0, 1\)"),
    ("nonocc dt 0", lambda p: NonOccurrence().step({}, 0.0), V, r"dt"),
    ("nonocc fall 1", lambda p: NonOccurrenceParams(fall_fraction=1.0), V, r"fall_fraction"),
    ("delay beyond battery", lambda p: (lambda c, b: c.step(b, 0.2))(*_timing_at_event(400.0)),
     DelayRangeWarning, r"400.*mu_max=120"),
    # --- transition graph
    ("graph negative a", lambda p: TransitionGraph().add_transition(-3, 2, "wait"), V,
     r"a must be a state id >= 0, got -3"),
    ("graph negative b", lambda p: TransitionGraph().add_transition(0, -1, "wait"), V,
     r"b must be a state id >= 0"),
    ("graph float id", lambda p: TransitionGraph().add_transition(1.5, 2, "wait"), V,
     r"integer state id, got 1\.5"),
    ("graph bool id", lambda p: TransitionGraph().add_transition(True, 2, "wait"), V,
     r"integer state id, got True"),
    ("graph text id", lambda p: TransitionGraph().add_transition("a", 2, "wait"), V,
     r"integer state id, got 'a'"),
    ("graph action fly", lambda p: TransitionGraph().add_transition(0, 1, "fly"), V,
     r"action must be"),
    ("graph action triple", lambda p: TransitionGraph().add_transition(0, 1, (1, 2, 3)), V,
     r"action must be"),
    ("graph heading NaN", lambda p: TransitionGraph().add_transition(0, 1, (math.nan, 1.0)), V,
     r"heading"),
    ("graph distance -1", lambda p: TransitionGraph().add_transition(0, 1, (0.0, -1.0)), V,
     r"distance"),
    ("graph delay -2", lambda p: TransitionGraph().add_transition(0, 1, "wait", -2.0), V,
     r"delay.*-2"),
    ("graph delay NaN", lambda p: TransitionGraph().add_transition(0, 1, "wait", math.nan), V,
     r"delay"),
    ("graph time inf", lambda p: TransitionGraph().add_transition(0, 1, "wait", time=math.inf),
     V, r"time"),
    ("graph move kind no heading", lambda p: Action("move"), V, r"heading"),
    ("graph kind", lambda p: Action("jump"), V, r"kind"),
    ("graph decay 1.5", lambda p: _graph().decay(1.5), V, r"decay factor"),
    ("graph decay threshold", lambda p: _graph().decay(0.5, threshold=-1.0), V,
     r"decay threshold"),
    ("graph state -1", lambda p: TransitionGraph().add_state(-1), V, r"state id >= 0"),
    ("graph position NaN", lambda p: TransitionGraph().add_state(0, (math.nan, 1.0)), V,
     r"position of state 0"),
    ("graph position 3", lambda p: TransitionGraph().add_state(0, (1.0, 2.0, 3.0)), V,
     r"position of state 0"),
    ("graph unknown state", lambda p: _graph().outgoing(99), K, r"unknown state 99"),
    ("graph unknown transition", lambda p: _graph().successors((5, 6)), K,
     r"unknown transition 5->6"),
    ("graph transition triple", lambda p: _graph().successors((1, 2, 3)), V, r"pair"),
    ("graphml delay -2", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, '<data key="d11">2.0</data>', '<data key="d11">-2.0</data>')), C,
     r"delay.*-2"),
    ("graphml delay NaN", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, '<data key="d11">2.0</data>', '<data key="d11">NaN</data>')), C,
     r"delay"),
    ("graphml count 0", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, '<data key="d4">1</data>', '<data key="d4">0</data>')), C,
     r"count"),
    ("graphml node id", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, 'node id="0-&gt;1"', 'node id="0-&gt;7"')), C, r"node id"),
    ("graphml format", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, "TransitionGraph/1", "TransitionGraph/9")), C,
     r"not a hippo transition graph"),
    ("graphml not xml", lambda p: TransitionGraph.from_graphml(
        _damaged_graphml(p, "<graphml", "<<graphml")), C, r"not a readable GraphML"),
    ("graphml missing", lambda p: TransitionGraph.from_graphml(p / "no.graphml"),
     FileNotFoundError, r"no\.graphml"),
    # --- drives and planner
    ("drives empty name", lambda p: Drives().add(""), V, r"non-empty string"),
    ("drives number name", lambda p: Drives().add(3), V, r"non-empty string, got 3"),
    ("drives twice", lambda p: _drives().add("food"), V, r"already exists"),
    ("drives params dict", lambda p: Drives().add("a", {"epsilon": 1}), TypeError,
     r"DriveParams"),
    ("drives level 1.5", lambda p: _drives().set_level("food", 1.5), V, r"level.*1\.5"),
    ("drives level NaN", lambda p: _drives().set_level("food", math.nan), V, r"level"),
    ("drives unknown", lambda p: _drives().level("water"), K, r"unknown drive 'water'"),
    ("drives step dt -1", lambda p: _drives().step(-1.0), V, r"dt"),
    ("drives step dt nan", lambda p: _drives().step(math.nan), V, r"dt"),
    ("drives epsilon -1", lambda p: DriveParams(epsilon=-1.0), V, r"epsilon"),
    ("drives learning_rate 0", lambda p: DriveParams(learning_rate=0.0), V, r"learning_rate"),
    ("drives load missing", lambda p: Drives.load(p / "d.json"), FileNotFoundError, r"d\.json"),
    ("drives load not json", lambda p: Drives.load(
        (p / "d.json", (p / "d.json").write_text("{"))[0]), C, r"not valid JSON"),
    ("drives load list", lambda p: Drives.load(
        (p / "d.json", (p / "d.json").write_text("[1]"))[0]), C, r"format"),
    ("drives load level 2", lambda p: Drives.load(
        (p / "d.json", (p / "d.json").write_text(
            _drives().save(p / "ok.json").read_text().replace('"level": 0.0',
                                                             '"level": 2.0')))[0]), C,
     r"level"),
    ("planner w 1", lambda p: PlannerParams(w=1.0), V, r"w"),
    ("planner method", lambda p: PlannerParams(method="bfs"), V, r"method"),
    ("planner threshold 2", lambda p: PlannerParams(exploration_threshold=2.0), V,
     r"exploration_threshold"),
    ("propagate inputs 1.5", lambda p: propagate(_graph(), {(0, 1): 1.5}, 0.9), V,
     r"drive inputs must lie in \[0, 1\]"),
    ("propagate unknown", lambda p: propagate(_graph(), {(7, 8): 0.5}, 0.9), K,
     r"unknown transition 7->8"),
    ("planner unknown state", lambda p: Planner().choose(_graph(), _drives(), 42,
                                                         np.random.default_rng(0)), K,
     r"unknown state 42"),
    # --- the agent's observation (one cheap check per tick)
    ("agent t nan", lambda p: _agent_step(t=math.nan), V, r"obs\.t must be a finite time"),
    ("agent t inf", lambda p: _agent_step(t=math.inf), V, r"obs\.t"),
    ("agent t backwards", lambda p: _agent_step(t=-0.2), V, r"clock must not run backwards"),
    ("agent t text", lambda p: _agent_step(t="0.4"), V, r"obs\.t"),
    ("agent ir x50", lambda p: _agent_step(ir=np.full(8, 50.0)), V, r"in \[0, 1\]"),
    ("agent ir None", lambda p: _agent_step(ir=None), V, r"obs\.ir must have shape \(8,\)"),
    ("agent ir NaN", lambda p: _agent_step(ir=np.full(8, np.nan)), V, r"obs\.ir"),
    ("agent ir 5", lambda p: _agent_step(ir=np.zeros(5)), V, r"shape \(8,\)"),
    ("agent ir text", lambda p: _agent_step(ir="abcdefgh"), V, r"obs\.ir"),
    ("agent odometry 2", lambda p: _agent_step(odometry=np.zeros(2)), V, r"obs\.odometry"),
    ("agent odometry NaN", lambda p: _agent_step(odometry=np.full(3, np.nan)), V,
     r"obs\.odometry"),
    ("agent floor -1", lambda p: _agent_step(floor=-1), V, r"obs\.floor"),
    ("agent floor 1.5", lambda p: _agent_step(floor=1.5), V, r"obs\.floor"),
    ("agent sound text", lambda p: _agent_step(sound="yes"), V, r"obs\.sound"),
    ("agent moving None", lambda p: _agent_step(moving=None), V, r"obs\.moving"),
    ("agent obs dict", lambda p: _agent_step_raw({"ir": np.zeros(8), "t": 1.0}), V,
     r"obs must be an Observation.*dict"),
    ("agent obs None", lambda p: _agent_step_raw(None), V, r"obs must be an Observation"),
    # --- world and recordings
    ("world step 3 values", lambda p: _world().step((1.0, 2.0, 3.0)), V,
     r"pair of wheel speeds \(left, right\).*\(1\.0, 2\.0, 3\.0\)"),
    ("world step 1 value", lambda p: _world().step((1.0,)), V, r"pair"),
    ("world step text", lambda p: _world().step("ab"), V, r"pair"),
    ("world step None", lambda p: _world().step(None), V, r"pair"),
    ("world step dict", lambda p: _world().step({"left": 1, "right": 2}), V, r"pair"),
    ("world step NaN", lambda p: _world().step((math.nan, 0.0)), V, r"finite"),
    ("world step inf", lambda p: _world().step((0.0, math.inf)), V, r"finite"),
    ("world arena name", lambda p: World("two_rooms"), V, r"arena must be an Arena"),
    ("world dt 0", lambda p: World(arenas.get("two_rooms"), dt=0.0), V, r"dt"),
    ("world substeps 0", lambda p: World(arenas.get("two_rooms"), substeps=0), V, r"substeps"),
    ("world substeps 2.5", lambda p: World(arenas.get("two_rooms"), substeps=2.5), V,
     r"substeps"),
    ("world seed -1", lambda p: World(arenas.get("two_rooms"), seed=-1), V, r"seed"),
    ("world sensors ir9", lambda p: World(arenas.get("two_rooms"), sensors="ir9"), V,
     r"unknown sensor model 'ir9'"),
    ("world sensors list", lambda p: World(arenas.get("two_rooms"), sensors=["ir8"]), V,
     r"sensors must be"),
    ("world robot dict", lambda p: World(arenas.get("two_rooms"), robot={"radius": 3}), V,
     r"robot must be RobotParams"),
    ("arena unknown", lambda p: arenas.get("moon"), V, r"unknown arena 'moon'"),
    ("arena number", lambda p: arenas.get(3), V, r"arena name must be a string"),
    ("record ticks 0", lambda p: record("two_rooms", 0), V, r"ticks"),
    ("record ticks 10.5", lambda p: record("two_rooms", 10.5), V, r"ticks.*10\.5"),
    ("record arena unknown", lambda p: record("moon", 10), V, r"unknown arena"),
    ("sensor model no rays", lambda p: SensorModel("x", ()), V, r"ray"),
    ("sensor model range", lambda p: SensorModel("x", (0.0,), 30.0, 4.0), V, r"range"),
    ("robot noise -1", lambda p: RobotParams(odometry_noise=-1.0), V, r"odometry_noise|noise"),
]


@pytest.mark.parametrize(("call", "exc", "pattern"),
                         [pytest.param(c, e, m, id=i) for i, c, e, m in CASES])
def test_bad_input_is_refused_clearly(tmp_path, call, exc, pattern):
    if issubclass(exc, Warning):
        with warnings.catch_warnings():
            warnings.simplefilter("error", exc)
            with pytest.raises(exc, match=pattern):
                call(tmp_path)
        return
    with pytest.raises(exc, match=pattern):
        call(tmp_path)


def test_the_table_covers_at_least_200_api_cases():
    assert len(CASES) + len(_generated_cases()) >= 200
    assert len(CASES) >= 150


def test_out_of_range_policy_warn_clips_and_warns():
    m = RCSFAICA(n_reservoir=20, ica_restarts=1, out_of_range="warn").fit(_U())
    clipped = np.clip(_U()[0] * 1e6, 0, 1)
    m.reset_state()
    with pytest.warns(InputRangeWarning, match="outside input_range"):
        a = m.step(_U()[0] * 1e6)
    m.reset_state()
    assert np.array_equal(a, m.step(clipped))
    assert np.abs(a).max() < 1e3  # never extrapolated to +-1e4


def test_out_of_range_policy_clip_is_silent_and_bounded():
    m = RCSFAICA(n_reservoir=20, ica_restarts=1, out_of_range="clip").fit(_U())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = m.transform(_U() * 1e6)
    assert np.array_equal(out, m.transform(np.clip(_U() * 1e6, 0, 1)))


def test_input_range_none_accepts_any_finite_scale():
    U = _U() * 100
    m = RCSFAICA(n_reservoir=20, ica_restarts=1, input_range=None).fit(U)
    assert np.isfinite(m.step(U[0])).all()
    with pytest.raises(ValueError, match="NaN"):
        m.step(np.full(8, np.nan))


def test_cuda_device_without_cuda_fails_at_construction():
    try:
        import torch
    except ImportError:
        with pytest.raises(ImportError, match=r"hippo\[torch\]"):
            RCSFAICA(device="cuda")
        return
    if torch.cuda.is_available():
        pytest.skip("this machine has CUDA")
    with pytest.raises(ValueError, match=r"device='cuda'.*no CUDA"):
        RCSFAICA(device="cuda")

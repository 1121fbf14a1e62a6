"""Exploration's rules on small hand-made cases: the tour's views, the pauses against the
documented seed stream, the log rows, the replay skipping pauses (a stand-in agent records
what it is given), the place sources' settings, wall_side's laps and backward share exactly
on OUTER_MIN_LAPS / OUTER_MAX_BACK and one step past (stand-in probes), wall_tour's loop on a
hand-made square path, arena_tour's caches, and every refusal word for word."""

from __future__ import annotations

import importlib
import math
import warnings
from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import pytest

from hippo.places import GroundTruthPlaceCells, LearnedPlaceCells
from hippo.seeds import Seeds
from hippo.sim import ArenaBuilder, World
from hippo.sim.controllers import WallFollower, WallFollowerParams
from hippo.sim.robot import RobotParams
from hippo.tasks.log import Log
from hippo.types import GroundTruth, Observation

# the module, not the function hippo.tasks exports under the same name
ex = importlib.import_module("hippo.tasks.explore")


def _box(w: float = 80.0, locations: bool = False):
    b = ArenaBuilder("box", w, 60).outer_walls().start(20, 20, 0.0)
    if locations:
        b = b.grid_locations(2, 2)
    return b.build()


def _obs(t: float, ir: float = 0.0, moving: bool = True,
         odo: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Observation:
    return Observation(t=t, tick=0, ir=np.full(8, ir), floor=0, sound=False,
                       odometry=np.array(odo), moving=moving)


def _truth(x: float, y: float, h: float = 0.0) -> GroundTruth:
    return GroundTruth(t=0.0, tick=0, pose=(x, y, h), speed=0.0)


# -- the tour and explore ------------------------------------------------------------------------
def test_the_tour_views():
    tour = ex.Tour([_obs(0.0, 0.25), _obs(0.2, 0.5, moving=False)], [_truth(1, 2), _truth(3, 4)])
    assert len(tour) == 2 and tour[1] is tour.observations[1]
    assert list(tour) == tour.observations
    np.testing.assert_array_equal(tour.sensors, [[0.25] * 8, [0.5] * 8])
    assert tour.moving.dtype == bool and list(tour.moving) == [True, False]
    assert len(ex.Tour()) == 0 and ex.Tour().observations is not ex.Tour().observations


def _recording(world: World) -> list[tuple[float, float]]:
    actions: list[tuple[float, float]] = []
    step = world.step

    def rec(a: Any) -> Observation:
        actions.append(tuple(a))
        return step(a)

    world.step = rec                    # type: ignore[method-assign]
    return actions


def test_pauses_follow_the_pause_stream_and_last_2_to_30_s():
    # the schedule worked out from Seeds(seed).generator("pauses") on its own: a draw per
    # tick not paused, a pause of int(U(2, 30) / dt) ticks of (0, 0) after a draw < rate
    world = World(_box(), seed=0)
    actions = _recording(world)
    log = Log()
    tour = ex.explore(world, 300, 0.0, 5, log, pause_rate=0.05, phase=3)
    rng, pause, still = Seeds(5).generator("pauses"), 0, []
    for _ in range(300):
        if pause > 0:
            pause -= 1
            still.append(True)
        else:
            if rng.random() < 0.05:
                pause = int(rng.uniform(2.0, 30.0) / 0.2)
            still.append(False)
    assert any(still) and not all(still)
    assert [a == (0.0, 0.0) for a in actions] == still
    assert len(tour) == len(tour.truths) == len(log) == 300
    # the log's rows: the tour's truths, under the phase, trial -1, no agent
    np.testing.assert_array_equal(log.column("x"), [t.pose[0] for t in tour.truths])
    np.testing.assert_array_equal(log.column("t"), [o.t for o in tour.observations])
    assert set(log.column("phase")) == {3} and set(log.column("trial")) == {-1}
    assert set(log.column("winner")) == {-1}
    assert tour.truths[-1] == world.truth and tour.observations[0].tick == 1
    log = Log()
    ex.explore(World(_box(), seed=0), 3, 0.0, 5, log)
    assert list(log.column("phase")) == [0, 0, 0]             # phase 0 by default


def test_explore_is_the_seeded_wall_follower_on_the_side_given():
    # the same wall follower built by hand (rho, the "exploration" stream, the side) drives
    # a second world; without pauses both run the same poses
    arena = _box()
    for side, rho, robot in ((1, 0.0, None), (-1, 0.3, None), (1, 0.0, RobotParams(axle=8.0))):
        world = World(arena, robot=robot, seed=0)
        tour = ex.explore(world, 120, rho, 4, pause_rate=0.0, side=side)
        other = World(arena, robot=robot, seed=0)      # the world's own robot drives it
        ctrl = WallFollower(WallFollowerParams(rho=rho), sensors=other.sensors,
                            robot=other.robot, rng=Seeds(4).generator("exploration"),
                            side=side)
        obs, poses = other.observe(), []
        for _ in range(120):
            obs = other.step(ctrl.act(obs))
            poses.append(other.truth.pose)
        assert [t.pose for t in tour.truths] == poses
    left = ex.explore(World(arena, seed=0), 120, 0.0, 4, pause_rate=0.0, side=1)
    right = ex.explore(World(arena, seed=0), 120, 0.0, 4, pause_rate=0.0)   # right by default
    assert [t.pose for t in left.truths] != [t.pose for t in right.truths]


def test_the_default_pause_rate_is_the_documented_one():
    assert ex.PAUSE_RATE == 0.003
    a = ex.explore(World(_box(), seed=0), 600, 0.0, 1)
    b = ex.explore(World(_box(), seed=0), 600, 0.0, 1, pause_rate=0.003)
    assert [t.pose for t in a.truths] == [t.pose for t in b.truths]
    c = ex.explore(World(_box(), seed=0), 600, 0.0, 1, pause_rate=0.0)   # seed 1 pauses
    assert [t.pose for t in a.truths] != [t.pose for t in c.truths]


# -- learn_map -----------------------------------------------------------------------------------
class _Agent:
    def __init__(self, kind: str) -> None:
        self.places = SimpleNamespace(kind=kind)
        self.given: list[tuple[Observation, Any]] = []

    def step(self, obs: Observation, truth: Any) -> None:
        self.given.append((obs, truth))


def test_learn_map_skips_the_pauses_and_gives_truth_only_to_ground_truth_cells():
    obs = [_obs(0.2), _obs(0.4, moving=False), _obs(0.6, moving=False, odo=(0.0, 0.0, 0.1)),
           _obs(0.8, moving=False, odo=(0.5, 0.0, 0.0)), _obs(1.0)]
    truths = [_truth(i, 0) for i in range(5)]
    tour = ex.Tour(obs, truths)
    agent = _Agent("learned")
    ex.learn_map(agent, tour)
    # tick 1 neither moved nor turned: left out; a turn or any odometry counts
    assert [o for o, _ in agent.given] == [obs[0], obs[2], obs[3], obs[4]]
    assert [t for _, t in agent.given] == [None] * 4
    agent = _Agent("ground-truth")
    ex.learn_map(agent, tour)
    assert [t for _, t in agent.given] == [truths[0], truths[2], truths[3], truths[4]]
    agent = SimpleNamespace(places=object(), given=[])        # no kind: no truth
    agent.step = lambda o, t: agent.given.append(t)
    ex.learn_map(agent, tour)
    assert agent.given == [None] * 4


# -- the place sources ---------------------------------------------------------------------------
def test_make_places_ground_truth_fields_and_the_refusal():
    arena = _box(locations=True)
    cells = ex.make_places("ground-truth", arena, np.zeros((10, 8)), 4, 0)
    assert isinstance(cells, GroundTruthPlaceCells) and cells.sigma == 8.0
    np.testing.assert_array_equal(cells.centres, arena.locations)
    with pytest.raises(ValueError) as e:
        ex.make_places("Learned", arena, np.zeros((10, 8)), 4, 0)
    assert str(e.value) == "place cells must be 'learned' or 'ground-truth', got 'Learned'"


def test_place_model_settings():
    m = ex.place_model(6, seed=9)
    p = m.params
    assert (p.n_reservoir, tuple(p.leak), p.spectral_radius) == (400, (0.1, 0.3), 0.9)
    assert (p.n_sfa, p.n_ica, p.ica_restarts, p.seed) == (6, 6, 3, 9)
    assert ex.place_model(5).params.seed == 0


def _wander(T: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.cumsum(rng.normal(0.0, 0.05, (T, 8)), axis=0) % 1.0


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_make_places_learned_fits_the_model_and_the_prototypes_on_the_tour():
    # the recipe done by hand with the public parts: the same model, the same prototypes
    from hippo.perception.prototypes import PlacePrototypes, PrototypeParams
    from hippo.perception.relocate import SequenceRelocaliser

    S = _wander(420, 0)
    cells = ex.make_places("learned", None, S, 4, 3, n_places=5)   # type: ignore[arg-type]
    assert isinstance(cells, LearnedPlaceCells) and cells.relocaliser is None
    assert cells.n_units == 5 and cells.prototypes.params == PrototypeParams(5, seed=3)
    model = ex.place_model(4, 3)
    Y = model.fit_transform(S)
    protos = PlacePrototypes(PrototypeParams(n_prototypes=5, seed=3)).fit(Y)
    np.testing.assert_array_equal(cells.prototypes.centres_, protos.centres_)
    # the online loop starts afresh (reset after the fit): as the hand-fitted model reset
    model.reset_state()
    np.testing.assert_array_equal(cells.model.step(S[0]), model.step(S[0]))
    assert ex.make_places("learned", None, S, 4, 3).n_units == 32   # type: ignore[arg-type]
    moving = np.ones(420, bool)
    moving[::7] = False
    cells = ex.make_places("learned", None, S, 4, 3, n_places=5, moving=moving)  # type: ignore
    rel = cells.relocaliser
    assert isinstance(rel, SequenceRelocaliser) and rel.reservoir is cells.model.reservoir_
    np.testing.assert_array_equal(rel.moving_ticks, np.flatnonzero(moving))
    np.testing.assert_array_equal(rel.sensors, S)
    # the place code's winner at each moving tick: the hand-fitted prototypes' argmax
    np.testing.assert_array_equal(rel.winners, np.argmax(protos.transform(Y), axis=1)[moving])


# -- wall_side -----------------------------------------------------------------------------------
class _ProbeWorld:
    dt = 0.5
    made: ClassVar[list[tuple[Any, int]]] = []

    def __init__(self, arena: Any, seed: int) -> None:
        _ProbeWorld.made.append((arena, seed))
        self.truth = _truth(-1.0, -2.0)


def _probes(monkeypatch: pytest.MonkeyPatch, runs: dict[int, tuple[float, list[float]]]
            ) -> list[dict[str, Any]]:
    """wall_side's probe on stand-ins: per side, the laps counted and the progress the lap
    counter reads tick by tick (it reads 0 at the start)."""
    calls: list[dict[str, Any]] = []
    _ProbeWorld.made = []

    def explore(world: Any, ticks: int, rho: float, seed: int, **kw: Any) -> ex.Tour:
        side = kw["side"]
        calls.append({"world": world, "ticks": ticks, "rho": rho, "seed": seed, **kw})
        prog = runs[side][1]
        return ex.Tour([], [_truth(p, float(side)) for p in prog])

    class Lap:
        def __init__(self, route: Any) -> None:
            self.route, self.side, self.turns = route, None, 0.0
            self.starts: list[tuple[float, float]] = []

        def update(self, x: float, y: float) -> float:
            if self.side is None:                        # the start: (-1, -2)
                assert (x, y) == (-1.0, -2.0)
                self.side = 0
                return 0.0
            self.turns = runs[int(y)][0]
            return x

    monkeypatch.setattr(ex, "World", _ProbeWorld)
    monkeypatch.setattr(ex, "explore", explore)
    monkeypatch.setattr(ex, "LapCounter", Lap)
    return calls


def test_wall_side_probes_each_side_in_a_world_of_its_own(monkeypatch):
    calls = _probes(monkeypatch, {-1: (1.0, [0.5]), 1: (0.0, [0.5])})
    route = SimpleNamespace(winding=-1)
    arena = object()
    # clockwise: the outer wall is the left (+1); it made 0 laps, the right 1: right
    assert ex.wall_side(route, arena, 7, 300.0) == -1     # type: ignore[arg-type]
    assert [c["side"] for c in calls] == [-1, 1]
    assert _ProbeWorld.made == [(arena, 7), (arena, 7)]
    for c in calls:
        assert (c["ticks"], c["rho"], c["seed"], c["pause_rate"]) == (600, 0.0, 7, 0.0)
    assert calls[0]["world"] is not calls[1]["world"]
    assert [c["desc"] for c in calls] == ["probing the right wall", "probing the left wall"]
    calls.clear()
    ex.wall_side(route, arena)                             # type: ignore[arg-type]
    assert calls[0]["ticks"] == 1200 and calls[0]["seed"] == 0   # 600 s at dt 0.5


def test_a_route_out_and_back_keeps_the_right_wall_unprobed(monkeypatch):
    calls = _probes(monkeypatch, {})
    assert ex.wall_side(SimpleNamespace(winding=0), object()) == -1   # type: ignore[arg-type]
    assert calls == []


# progress read tick by tick: 9/16 on, 1/16 back: 1/16 of 10/16 moved backwards, exactly 0.1
EDGE = [0.5625, 0.5]
PAST = [0.5, 0.4375]     # 1/16 of 9/16 backwards: 0.111 > 0.1


@pytest.mark.parametrize(("winding", "runs", "want"), [
    # counter-clockwise: the outer wall is the right (-1); it wins exactly on the bounds ...
    (1, {-1: (1.0, EDGE), 1: (5.0, [1.0])}, -1),
    # ... and loses one step past either (the left goes farther round: +1)
    (1, {-1: (1.0, PAST), 1: (5.0, [1.0])}, 1),
    (1, {-1: (0.9375, EDGE), 1: (5.0, [1.0])}, 1),
    # clockwise: the outer wall is the left (+1)
    (-1, {-1: (5.0, [1.0]), 1: (1.0, EDGE)}, 1),
    (-1, {-1: (5.0, [1.0]), 1: (1.0, PAST)}, -1),
    # a follower that did not move has all its progress "backwards" (share 1)
    (1, {-1: (2.0, [0.0, 0.0]), 1: (3.0, [1.0])}, 1),
    # no outer wall: the side that goes farther round, ties and no way round to the right
    (-1, {-1: (0.5, PAST), 1: (0.5, PAST)}, -1),
    (-1, {-1: (0.25, PAST), 1: (0.5, PAST)}, 1),
    (-1, {-1: (-1.0, PAST), 1: (-0.5, PAST)}, -1),
    (-1, {-1: (-1.0, PAST), 1: (0.0, PAST)}, -1),
])
def test_wall_side_bounds_on_their_edges_and_one_step_past(monkeypatch, winding, runs, want):
    assert (ex.OUTER_MIN_LAPS, ex.OUTER_MAX_BACK) == (1.0, 0.1)
    _probes(monkeypatch, runs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")         # no 0 / 0 for a follower that did not move
        assert ex.wall_side(SimpleNamespace(winding=winding), object()) == want  # type: ignore


# -- wall_tour and arena_tour --------------------------------------------------------------------
def _square(side: float, step: float, laps: int, start: int = 0) -> list[GroundTruth]:
    """Poses round a square (corner (0, 0), counter-clockwise) every ``step`` cm."""
    n = int(side / step)
    pts = []
    for k in range(4 * n * laps + 1):
        s = ((k + start) % (4 * n)) * step
        leg, d = divmod(s, side)
        x, y, h = [(d, 0.0, 0.0), (side, d, math.pi / 2), (side - d, side, math.pi),
                   (0.0, side - d, -math.pi / 2)][int(leg)]
        pts.append(_truth(x, y, h))
    return pts


def _tour_world(monkeypatch: pytest.MonkeyPatch, truths: list[GroundTruth]) -> list[dict]:
    calls: list[dict] = []

    class W:
        dt = 0.5

        def __init__(self, arena: Any, seed: int) -> None:
            calls.append({"arena": arena, "world_seed": seed})

    def explore(world: Any, ticks: int, rho: float, seed: int, **kw: Any) -> ex.Tour:
        calls.append({"ticks": ticks, "rho": rho, "seed": seed, **kw})
        return ex.Tour([], truths)

    monkeypatch.setattr(ex, "World", W)
    monkeypatch.setattr(ex, "explore", explore)
    return calls


def test_wall_tour_is_one_loop_from_the_settled_pose(monkeypatch):
    # a 40-cm square run at 4 cm a tick: from tick 2 (1 s settled at dt 0.5) the follower is
    # back 40 ticks (160 cm) later; the route is that loop, a point every 3 cm from (8, 0)
    calls = _tour_world(monkeypatch, _square(40.0, 4.0, 3))
    route = ex.wall_tour("arena", 1, seed=4, max_s=10.0, settle_s=1.0)  # type: ignore[arg-type]
    assert calls == [{"arena": "arena", "world_seed": 4},
                     {"ticks": 20, "rho": 0.0, "seed": 4, "pause_rate": 0.0, "side": 1,
                      "desc": "wall tour"}]
    assert route is not None and route.closed
    # arc s from (8, 0) round the square: (8 + s, 0) up to s = 32, then up the side x = 40 ...
    s = np.arange(0.0, 160.0, 3.0)
    want = [(8 + v, 0.0) if v <= 32 else (40.0, v - 32) if v <= 72 else (112 - v, 40.0)
            if v <= 112 else (0.0, 152 - v) if v <= 152 else (v - 152, 0.0) for v in s]
    np.testing.assert_allclose(route.points, want, atol=1e-9)
    # the default spacing, 3 cm; another: 5 cm
    r5 = ex.wall_tour("arena", 1, max_s=10.0, settle_s=1.0, spacing=5.0)  # type: ignore
    assert r5 is not None and len(r5.points) == 32


def test_wall_tour_needs_more_than_100_cm_within_4_cm_facing_the_same_way(monkeypatch):
    # a 25-cm square at 5 cm a tick: back after exactly 100 cm (not more): the next lap's
    # return, 200 cm on, closes it
    _tour_world(monkeypatch, _square(25.0, 5.0, 3))
    route = ex.wall_tour("a", settle_s=0.0, spacing=5.0)      # type: ignore[arg-type]
    assert route is not None and len(route.points) == 40
    # two laps of the square's 20 corners and edge points, from (0, 0)
    lap = [(t.pose[0], t.pose[1]) for t in _square(25.0, 5.0, 1)[:-1]]
    np.testing.assert_allclose(route.points, lap + lap, atol=1e-9)
    # back at (0.5, 0) after 95 + hypot(0.5, 5) = 100.02 cm: just over 100, closed there
    sq = _square(25.0, 5.0, 1)
    _tour_world(monkeypatch, [*sq[:-1], _truth(0.5, 0.0, 0.0)])
    route = ex.wall_tour("a", settle_s=0.0, spacing=5.0)      # type: ignore[arg-type]
    assert route is not None and len(route.points) == 21      # 0, 5, ..., 100
    # never back: None; settled beyond the tour: its last pose, never come back to
    _tour_world(monkeypatch, _square(40.0, 4.0, 3)[:30])
    assert ex.wall_tour("a", settle_s=0.0) is None            # type: ignore[arg-type]
    _tour_world(monkeypatch, _square(40.0, 4.0, 3))
    assert ex.wall_tour("a", settle_s=1e6) is None            # type: ignore[arg-type]
    # back 4 cm off the settled point (the square shifted 4 cm up): not back
    sq = _square(40.0, 4.0, 1)
    shifted = [_truth(t.pose[0], t.pose[1] + (4.0 if k > 10 else 0.0), t.pose[2])
               for k, t in enumerate(sq)]
    _tour_world(monkeypatch, shifted)
    assert ex.wall_tour("a", settle_s=0.0) is None            # type: ignore[arg-type]
    shifted = [_truth(t.pose[0], t.pose[1] + (3.9 if k > 10 else 0.0), t.pose[2])
               for k, t in enumerate(sq)]
    _tour_world(monkeypatch, shifted)
    assert ex.wall_tour("a", settle_s=0.0) is not None        # type: ignore[arg-type]
    # back at the point facing the other way: not back
    turned = [_truth(*t.pose[:2], t.pose[2] + (math.pi if k > 10 else 0.0))
              for k, t in enumerate(sq)]
    _tour_world(monkeypatch, turned)
    assert ex.wall_tour("a", settle_s=0.0) is None            # type: ignore[arg-type]
    # back at the point turned by acos(0.8) (cos exactly 0.8, checked): not back; by less: back
    assert math.cos(math.acos(0.8)) == 0.8
    for h, back in ((math.acos(0.8), False), (math.acos(0.81), True)):
        _tour_world(monkeypatch, [*sq[:-1], _truth(*sq[-1].pose[:2], h)])
        assert (ex.wall_tour("a", settle_s=0.0) is not None) is back  # type: ignore[arg-type]


def test_wall_tour_runs_1500_s_settles_30_s_by_default(monkeypatch):
    calls = _tour_world(monkeypatch, _square(40.0, 4.0, 3, start=0))
    route = ex.wall_tour("a")                                  # type: ignore[arg-type]
    assert calls[0]["world_seed"] == 0 and calls[1]["ticks"] == 3000
    assert calls[1]["side"] == -1 and calls[1]["seed"] == 0
    # settled at tick 60 (30 s at dt 0.5): 60 ticks of 4 cm = 1.5 laps, at (40, 40)
    assert route is not None and tuple(route.points[0]) == (40.0, 40.0)


def test_arena_tour_refusals_word_for_word():
    for side in (0, 2, -2, "1", True, 1.0, -1.0):
        with pytest.raises(ValueError) as e:
            ex.arena_tour("goal-arena", side)                  # type: ignore[arg-type]
        assert str(e.value) == f"side must be -1 (right wall) or +1 (left wall), got {side!r}"
    with pytest.raises(TypeError) as e2:
        ex.arena_tour(3)                                       # type: ignore[arg-type]
    assert str(e2.value) == "arena must be an arena's name or an Arena, got int"


def test_arena_tour_caches_by_name_and_by_arena(monkeypatch):
    made: ClassVar[list[tuple[Any, int]]] = []

    def wall_tour(arena: Any, side: int = -1) -> Any:
        made.append((arena, side))
        return ("tour", len(made))

    monkeypatch.setattr(ex, "wall_tour", wall_tour)
    monkeypatch.setattr(ex, "_OWN_TOURS", {})
    ex._arena_tour.cache_clear()
    try:
        from hippo.sim import arenas

        first = ex.arena_tour("two-rooms")
        assert ex.arena_tour("two-rooms", -1) is first and first == ("tour", 1)
        assert made[0][0].name == arenas.get("two-rooms").name and made[0][1] == -1
        assert ex.arena_tour("two-rooms", 1) == ("tour", 2) and made[1][1] == 1
        a = _box()
        t = ex.arena_tour(a)
        assert ex.arena_tour(a) is t and made[-1] == (a, -1) and len(made) == 3
        assert ex.arena_tour(a, 1) == ("tour", 4)
        # an arena at the address of one gone is not taken for it
        b = _box()
        ex._OWN_TOURS[(id(b), -1)] = (a, "stale")
        assert ex.arena_tour(b) == ("tour", 5)
        # at most 16 kept: the oldest goes first
        keep = [_box() for _ in range(16)]
        for k in keep:
            ex.arena_tour(k)
        assert len(ex._OWN_TOURS) == 16
        assert (id(a), -1) not in ex._OWN_TOURS and (id(keep[0]), -1) in ex._OWN_TOURS
        n = len(made)
        ex.arena_tour(keep[0])
        assert len(made) == n
    finally:
        ex._arena_tour.cache_clear()


def test_the_progress_bars_name_their_work_and_count_every_tick(monkeypatch):
    bars: list[list[Any]] = []

    class Bar:
        def __init__(self, total: int, desc: str) -> None:
            bars.append([total, desc, 0])

        def __enter__(self) -> Bar:
            return self

        def __exit__(self, *a: Any) -> None:
            pass

        def update(self) -> None:
            bars[-1][2] += 1

    monkeypatch.setattr(ex, "Progress", Bar)
    tour = ex.explore(World(_box(), seed=0), 12, 0.0, 0)
    ex.explore(World(_box(), seed=0), 3, 0.0, 0, desc="mine")
    ex.learn_map(_Agent("learned"), tour)
    ex.learn_map(_Agent("learned"), ex.Tour([_obs(0.0, moving=False)], [_truth(0, 0)]),
                 desc="again")
    # every tick counted, paused or skipped alike
    assert bars == [[12, "exploration", 12], [3, "mine", 3], [12, "map learning", 12],
                    [1, "again", 1]]
    shown: list[str] = []

    class Working:
        def __init__(self, desc: str) -> None:
            shown.append(desc)

        def __enter__(self) -> None:
            return None

        def __exit__(self, *a: Any) -> None:
            pass

    monkeypatch.setattr(ex, "working", Working)
    with pytest.raises(ValueError):
        ex.make_places("learned", _box(), np.zeros((5, 8)), 4, 0)      # too short to fit
    assert shown == ["fitting place cells"]


def test_wall_tour_refuses_times_and_spacing_that_are_no_positive_numbers():
    for name, bad in (("max_s", 0.0), ("settle_s", -30.0), ("spacing", float("nan")),
                      ("max_s", True), ("spacing", "3"), ("settle_s", -1e-9)):
        lo = ">=" if name == "settle_s" else ">"       # the tour may start at once
        with pytest.raises(ValueError) as e:
            ex.wall_tour(None, **{name: bad})                  # type: ignore[arg-type]
        assert str(e.value) == f"wall_tour's {name} must be a finite number {lo} 0, got {bad!r}"

"""Session and Log: the closed loop run, logged under named phases, written to run.npz."""

import math
from enum import IntEnum

import numpy as np
import pytest

from hippo.agent import Agent
from hippo.cognitive_map import DriveParams
from hippo.places import GroundTruthPlaceCells
from hippo.sim import ArenaBuilder, World
from hippo.tasks import Log, Session, enum_names, event_arrays
from hippo.types import Mode


class Phase(IntEnum):
    WARMUP = 0
    LEASH = 1


def _session():
    arena = ArenaBuilder("corridor", 200, 30).outer_walls().start(15, 15, 0.0).build()
    world = World(arena, seed=0)
    centres = np.array([[x, 15.0] for x in range(20, 200, 30)])
    agent = Agent(GroundTruthPlaceCells(centres, sigma=8.0),
                  drives={"check": DriveParams()}, sensors=world.sensors, robot=world.robot)
    return world, agent, Session(world, agent, phase=Phase.WARMUP)


def test_run_logs_every_tick_under_its_phase_and_stops_at_until(tmp_path):
    _, _, s = _session()
    s.run(seconds=2.0)
    assert len(s.log) == 10 and s.t == pytest.approx(2.0)
    s.phase, s.trial = Phase.LEASH, 3
    obs = s.run(500, until=lambda o: s.truth.pose[0] > 40.0)
    assert s.truth.pose[0] > 40.0 and obs is s.obs
    phase = s.log.column("phase")
    assert set(phase[:10]) == {0} and set(phase[10:]) == {1}
    assert set(s.log.column("trial", 10)) == {3}
    np.testing.assert_array_equal(s.log.column("x")[-1], s.truth.pose[0])
    with pytest.raises(ValueError, match="either ticks or seconds"):
        s.run(3, seconds=1.0)

    arrays = s.save(tmp_path / "out", Phase)
    with np.load(tmp_path / "out" / "run.npz") as z:
        assert list(z["phase_names"]) == ["warmup", "leash"]
        assert list(z["mode_names"]) == ["explore", "move", "approach", "wait"]
        assert list(z["drive_names"]) == ["check"]
        assert z["t"].shape == arrays["t"].shape == (len(s.log),)
    assert (tmp_path / "out" / "map.graphml").exists()


def test_a_lead_that_runs_out_of_ticks_drops_the_leash_and_says_so():
    from hippo.tasks.session import LeashWarning

    _, _, s = _session()
    with pytest.warns(LeashWarning, match="dropped after 10 ticks"):
        s.lead([(40.0, 15.0), (185.0, 15.0)], limit=10)    # 170 cm: far more than 10 ticks
    assert not s.teacher.leading                            # it pulled through every later phase
    x = s.truth.pose[0]
    s.lead([(x + 10.0, 15.0)], limit=2000)                  # a short lead ends by itself
    assert not s.teacher.leading


def test_the_teacher_block_and_the_kidnap():
    world, agent, s = _session()
    s.run(seconds=4.0)
    x0 = s.truth.pose[0]
    s.block(3.0)
    assert abs(s.truth.pose[0] - x0) < 3.0 and not s.teacher.blocking
    kinds = [k for _, k, _ in world.events]
    assert kinds[-2:] == ["block_start", "block_end"]
    s.put(150.0, 15.0, math.pi, event="kidnap")
    assert world.events[-1][1] == "kidnap"
    assert agent.brain.pi.heading == pytest.approx(math.pi, abs=0.3)  # turned by about pi
    assert agent.mode == Mode.EXPLORE and agent.state is None


def test_enum_names_and_events():
    assert list(enum_names(Phase)) == ["warmup", "leash"]

    class Gap(IntEnum):
        A = 0
        B = 2

    with pytest.raises(ValueError, match=r"0\.\.1"):
        enum_names(Gap)
    ev = event_arrays([(1.0, "sound", ""), (2.5, "block_start", "3.000")])
    np.testing.assert_array_equal(ev["event_t"], [1.0, 2.5])
    assert list(ev["event_kind"]) == ["sound", "block_start"]
    assert event_arrays([])["event_t"].shape == (0,)
    assert Log(n_drives=2).cols["drives"] == []


def test_path_length_starts_where_the_robot_was_put():
    # a straight drive down an open corridor: the path is the straight line, never shorter
    world, _, _ = _session()
    log = Log()
    world.place_robot(20.0, 15.0, 0.0)
    obs = world.step((0.0, 0.0))
    for _ in range(40):
        obs = world.step((5.0, 5.0))
        log.add(obs, world.truth, None, 0, 0)
    end = world.truth.pose[:2]
    straight = math.hypot(end[0] - 20.0, end[1] - 15.0)
    assert straight > 10.0
    assert log.path_length(0, (20.0, 15.0)) == pytest.approx(straight, rel=1e-3)
    # the rows alone miss the first step: the old measure fell below the shortest path
    rows_only = float(np.sum(np.hypot(np.diff(log.column("x")), np.diff(log.column("y")))))
    assert rows_only < straight - 0.1
    # cut at a time: the rows up to and including it
    t_half = log.column("t")[19]
    x_half = log.column("x")[19]
    assert log.path_length(0, (20.0, 15.0), t_half) == pytest.approx(x_half - 20.0, abs=0.05)


def test_run_refuses_a_length_that_is_no_whole_count_of_ticks_or_no_time():
    """The fourth fuzzing pass: -5 ran 0 ticks, 2.7 ran 2, "5" ran 5, seconds=-1 ran 0 in
    silence; NaN and inf seconds failed inside int()."""
    _, _, s = _session()
    for ticks, match in ((-5, r"ticks must be an integer >= 0, got -5"),
                         (2.7, r"ticks must be an integer, got 2\.7"),
                         ("5", r"ticks must be an integer, got '5'"),
                         (True, r"ticks must be an integer, got True")):
        with pytest.raises(ValueError, match=match):
            s.run(ticks)
    for seconds, match in ((-1.0, r"seconds must be >= 0, got -1\.0"),
                           (math.nan, r"seconds must be finite"),
                           (math.inf, r"seconds must be finite"),
                           ("5", r"seconds must be a real number")):
        with pytest.raises(ValueError, match=match):
            s.run(seconds=seconds)
    assert len(s.log) == 0 and s.world.tick == 0
    s.run(np.int64(3))
    s.run(0)
    s.run(seconds=0.4)
    assert len(s.log) == 5 and s.world.tick == 5


def test_put_refuses_a_heading_that_is_not_finite_before_anything_moves():
    """The fourth fuzzing pass: put(50, 50, inf) was taken, and the next tick failed with "math
    domain error"; Agent.lifted(heading_change=nan) made the heading estimate NaN."""
    world, agent, s = _session()
    s.run(5)
    pose, heading = world.pose, agent.brain.pi.heading
    for h in (math.inf, math.nan, "1.0"):
        with pytest.raises(ValueError, match="heading must be"):
            s.put(100.0, 15.0, h)
        with pytest.raises(ValueError, match="heading_change must be"):
            agent.lifted(heading_change=h)
    assert world.pose == pose and agent.brain.pi.heading == heading
    assert [e for e in world.events if e[1] == "kidnap"] == []
    s.put(100.0, 15.0, 1.0)
    s.run(3)
    assert math.isfinite(agent.brain.pi.heading) and len(s.log) == 8


def test_a_kidnap_keeps_the_heading_estimate_exact_even_mid_turn():
    # the robot is lifted while turning: the last observation's rotation, which the agent has
    # not integrated yet, must count (it was lost before: up to 0.5 rad per lift)
    _, agent, s = _session()
    s.run(seconds=2.0)
    s.run(400, until=lambda o: abs(o.odometry[2]) > 0.05)
    assert abs(s.obs.odometry[2]) > 0.05
    s.put(150.0, 15.0, 2.0)
    assert agent.brain.pi.heading == pytest.approx(2.0, abs=1e-9)


def test_a_lesson_that_needed_the_leash_is_given_again_after_the_one_before_it():
    from hippo.tasks.teaching import lessons_again

    order, again = [0, 1, 2, 0], set()
    lessons_again(order, 2, again)            # checkpoint 2 needed the leash: 1, 2 again
    assert order == [0, 1, 2, 0, 1, 2]
    lessons_again(order, 2, again)            # once per checkpoint
    lessons_again(order, 0, again)            # 0 is taught twice anyway
    lessons_again(order, 3, again)
    assert order == [0, 1, 2, 0, 1, 2] and again == {2}


def test_lessons_given_again_form_one_chain_when_two_needed_the_leash():
    from hippo.tasks.teaching import lessons_again

    # 1 and then 2 needed the leash: 1 is not taught twice in a row (its run-up would be a
    # whole lap), the repeated lessons run 0 -> 1 -> 2 like the first ones
    order, again = [0, 1, 2, 0], set()
    lessons_again(order, 1, again)
    assert order == [0, 1, 2, 0, 1]
    lessons_again(order, 2, again)
    assert order == [0, 1, 2, 0, 1, 2] and again == {1, 2}
    # the chain is the route's order, not the checkpoints' numbers
    order, again = [0, 2, 1, 0], set()
    lessons_again(order, 2, again)            # checkpoint 1, the route's third, went astray
    assert order == [0, 2, 1, 0, 2, 1]

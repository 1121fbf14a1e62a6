"""Head-direction sectors: the place state split by the direction of travel."""

import math

import numpy as np
import pytest

from hippo.brain import Brain, BrainParams
from hippo.cognitive_map import DriveParams
from hippo.head_direction import HeadingSectors
from hippo.perception.states import StateLayerParams
from hippo.types import Observation

DEG = math.pi / 180


def test_nearest_sector_is_the_one_whose_centre_is_closest():
    s = HeadingSectors(4)
    assert [s.nearest(h * DEG) for h in (0, 44, 46, 90, 179, 181, -90, -44, -46, 360)] == \
        [0, 0, 1, 1, 2, 2, 3, 0, 3, 0]
    assert [HeadingSectors(2).nearest(h * DEG) for h in (0, 89, 91, 180, -91)] == [0, 0, 1, 1, 1]


def test_split_puts_each_activity_in_its_sector_and_zeros_elsewhere():
    s = HeadingSectors(4)
    acts = np.array([0.2, 0.9, 0.5])
    out = s.split(acts, 90 * DEG, 1.0)     # sector 1
    assert out.shape == (12,)
    np.testing.assert_array_equal(out[1::4], acts)
    np.testing.assert_array_equal(np.delete(out, [1, 5, 9]), np.zeros(9))
    assert out.sum() == pytest.approx(acts.sum())
    # the winner keeps its place: argmax // n is the place, argmax % n the sector
    assert int(np.argmax(out)) // 4 == 1 and int(np.argmax(out)) % 4 == 1


def test_one_sector_passes_activities_through():
    acts = np.array([0.3, 0.1])
    assert HeadingSectors(1).split(acts, 2.0, 1.0) is acts


def test_hysteresis_keeps_the_sector_within_half_a_sector_plus_the_margin():
    s = HeadingSectors(4, margin=10 * DEG)
    assert s.update(0.0, 1.0) == 0
    assert s.update(54 * DEG, 1.0) == 0        # 45 + 10 not exceeded
    assert s.update(56 * DEG, 1.0) == 1        # now it is
    assert s.update(36 * DEG, 1.0) == 1        # 54 degrees off sector 1's centre: kept
    assert s.update(34 * DEG, 1.0) == 0        # 56 off: back
    # across the wrap: -170 degrees is sector 2 (centre 180) within the margin
    s.update(180 * DEG, 1.0)
    assert s.update(-170 * DEG, 1.0) == 2


def test_turning_on_the_spot_keeps_the_sector_until_the_robot_translates():
    s = HeadingSectors(4, min_step=0.1)
    s.update(0.0, 1.0)
    assert s.update(180 * DEG, 0.0) == 0       # turned round, not moved
    assert s.update(180 * DEG, 0.05) == 0
    assert s.update(180 * DEG, 0.5) == 2       # drives off the other way


def test_reset_takes_the_heading_as_it_is():
    s = HeadingSectors(4)
    s.update(0.0, 1.0)
    s.reset()
    assert s.update(math.pi, 0.0) == 2         # even without translating


@pytest.mark.parametrize("kw, match", [
    ({"n": 0}, "integer >= 1, got 0"), ({"n": 2.5}, "an integer, got 2.5"),
    ({"n": 4, "margin": 50 * DEG}, "below half a sector"), ({"n": 4, "margin": -0.1}, "margin"),
    ({"n": 4, "min_step": -1.0}, "min_step"),
])
def test_impossible_parameters_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        HeadingSectors(**kw)



def test_the_hysteresis_bound_and_the_translation_threshold_are_exact():
    n, margin = 4, 10 * DEG
    bound = 2 * math.pi / n / 2 + margin      # 55 degrees from the sector's centre
    s = HeadingSectors(n, margin=margin, min_step=0.1)
    s.update(0.0, 1.0)
    assert s.update(bound, 1.0) == 0           # exactly on the bound: kept (strictly beyond)
    assert s.update(math.nextafter(bound, 1.0), 1.0) == 1
    s.reset()
    s.update(0.0, 1.0)
    assert s.update(math.pi, 0.1) == 2         # exactly min_step: a translation
    # the offset from the sector's centre is taken the short way round the circle: sector 3
    # (centre 270 degrees) and a heading of -40 degrees (320, nearest sector 0) are 50 degrees
    # apart, within the hysteresis
    s.reset()
    s.update(270 * DEG, 1.0)
    assert s.update(-40 * DEG, 1.0) == 3
    assert s.update(-170 * DEG, 1.0) == 2      # 100 degrees the short way: sector 2


def test_a_zero_margin_or_min_step_is_allowed_and_the_margin_stays_below_half_a_sector():
    s = HeadingSectors(4, margin=0.0, min_step=0.0)
    s.update(0.0, 0.0)
    assert s.update(46 * DEG, 0.0) == 1        # no hysteresis, every step translates
    HeadingSectors(4, margin=0.6)              # above a third of a sector (0.52), below half
    with pytest.raises(ValueError, match=r"margin must be below half a sector \(0.785 rad\), "
                                         r"got 0.7853981"):
        HeadingSectors(4, margin=math.pi / 4)
    for kw, name in (({"n": 0}, "heading sectors"), ({"margin": -1.0}, "margin"),
                     ({"min_step": -1.0}, "min_step")):
        with pytest.raises(ValueError, match=rf"^{name} must"):
            HeadingSectors(**{"n": 4, **kw})
    with pytest.raises(ValueError, match=r"heading must be a finite number \(rad\)"):
        HeadingSectors(4).nearest(math.inf)

@pytest.mark.parametrize("heading, step, match", [
    (math.nan, 1.0, r"heading must be a finite number \(rad\), got nan"),
    (math.inf, 1.0, r"heading must be a finite number \(rad\), got inf"),
    ("1", 1.0, r"heading must be a finite number"),
    (0.0, math.nan, r"step must be a finite number >= 0 \(cm\), got nan"),
    (0.0, -1.0, r"step must be a finite number >= 0 \(cm\), got -1.0"),
])
def test_a_heading_or_step_that_is_no_finite_number_is_refused(heading, step, match):
    s = HeadingSectors(4)
    with pytest.raises(ValueError, match=match):  # before any sector is taken
        s.update(heading, step)
    assert s.sector is None
    s.update(math.pi / 2, 1.0)
    with pytest.raises(ValueError, match=match):  # (NaN used to keep the last sector silently)
        s.split(np.ones(3), heading, step)
    assert s.sector == 1
    with pytest.raises(ValueError, match="heading must be a finite number"):
        s.nearest(math.nan)


@pytest.mark.parametrize("bad", [0, -1, 1.5])
def test_brain_params_refuse_impossible_sector_counts(bad):
    with pytest.raises(ValueError, match="heading_sectors"):
        BrainParams(heading_sectors=bad)


class OnePlace:
    """A place source with one place that is always active (a symmetric room's stretch)."""

    kind = "stub"
    n_units = 2

    def step(self, obs, truth=None):
        return np.array([1.0, 0.0])

    def reset(self) -> None:
        pass

    def prime(self, sensors) -> None:
        pass


def _brain(sectors: int) -> Brain:
    p = BrainParams(settle_time=0.0, heading_sectors=sectors,
                    states=StateLayerParams(normalize="fixed", place_scale=0.5))
    return Brain(OnePlace(), drives={"sound": DriveParams()}, params=p)


def _winners(brain: Brain) -> list:
    """1 cm a tick east for 20 ticks, a half turn on the spot, 1 cm a tick west for 20."""
    out, t = [], 0
    legs = [((1.0, 0.0, 0.0), 20), ((0.0, 0.0, math.pi / 10), 10), ((1.0, 0.0, 0.0), 20)]
    for odo, n in legs:
        for _ in range(n):
            t += 1
            obs = Observation(round(t * 0.2, 9), t, np.full(8, 0.5), 0, False,
                              np.array(odo), True)
            out.append(brain.step(obs).winner)
    return out


def test_the_same_place_travelled_the_other_way_is_another_state():
    split = _winners(_brain(4))
    east, west = split[19], split[-1]
    assert east is not None and west is not None and east != west
    b = _brain(4)
    _winners(b)
    assert b.describe(east) == "place 0" and b.describe(west) == "place 2"   # sectors 0 and 2
    # the turn on the spot made no new state: the robot left the turn in the old one
    assert split[29] == east
    # without the split, one state throughout
    plain = _winners(_brain(1))
    assert plain[19] == plain[-1] is not None


def test_the_state_layer_has_a_place_input_per_place_and_sector():
    b = _brain(4)
    _winners(b)
    assert b.layer.place_activity.size == 8



def test_a_snapshot_keeps_the_sector(tmp_path):
    # (a whole robot with sectors is snapshotted by the patrol's --save test: learned cells
    # split in 4 by default)
    from hippo.snapshot import load_snapshot, save_snapshot
    a = HeadingSectors(4)
    a.update(3.0, 1.0)
    save_snapshot(a, tmp_path / "sectors")
    b = load_snapshot(tmp_path / "sectors", HeadingSectors)
    assert b.sector == a.sector == 2 and (b.n, b.width, b.margin) == (a.n, a.width, a.margin)
    acts = np.array([0.4, 0.7])
    for h, step in ((3.0, 1.0), (1.2, 0.0), (1.2, 1.0), (-1.6, 1.0)):
        np.testing.assert_array_equal(a.split(acts, h, step), b.split(acts, h, step))

"""Drives: build-up with epsilon, satisfaction, inhibition, goal links."""

from __future__ import annotations

import math

import pytest

from hippo.cognitive_map import DriveParams, Drives


def test_one_euler_step_matches_hand_computation():
    d = Drives({"sound": DriveParams(epsilon=0.5, initial=0.3)})
    d.step(0.2)
    assert d.level("sound") == pytest.approx(0.3 + 0.5 * 0.2 * (1 - 0.3))  # 0.37
    assert d.level("sound") == pytest.approx(0.37)


def test_closed_form_over_many_steps():
    eps, dt, d0, n = 0.05, 0.2, 0.1, 400
    d = Drives({"a": DriveParams(epsilon=eps, initial=d0), "b": DriveParams(epsilon=2 * eps)})
    for _ in range(n):
        d.step(dt)
    assert d.level("a") == pytest.approx(1 - (1 - d0) * (1 - eps * dt) ** n, rel=1e-12)
    assert d.level("b") == pytest.approx(1 - (1 - 2 * eps * dt) ** n, rel=1e-12)
    # and the continuous solution 1 - (1 - d0) exp(-eps t) for a small dt
    fine = Drives({"a": DriveParams(epsilon=eps, initial=d0)})
    for _ in range(20000):
        fine.step(0.004)
    assert fine.level("a") == pytest.approx(1 - (1 - d0) * math.exp(-eps * 80.0), abs=1e-4)
    assert 0 < d.level("a") < 1


def test_satisfaction_resets_then_rises_again():
    d = Drives({"food": DriveParams(epsilon=1.0, initial=0.8)})
    d.satisfy("food")
    assert d.level("food") == 0.0
    d.step(0.1)
    assert d.level("food") == pytest.approx(0.1)


def test_inhibition_holds_down_and_recovery_after_release():
    p = DriveParams(epsilon=0.5, initial=0.6)
    d = Drives({"cp": p, "other": p})
    for _ in range(30):
        d.step(0.2, inhibited={"cp"})
        assert d.level("cp") == 0.0
    assert d.level("other") == pytest.approx(1 - 0.4 * 0.9**30)  # unaffected
    for _ in range(10):
        d.step(0.2)
    assert d.level("cp") == pytest.approx(1 - 0.9**10)  # rises again from 0
    # persistent inhibition
    d.inhibit("other")
    assert d.is_inhibited("other") and d.level("other") == 0.0
    for _ in range(5):
        d.step(0.2)
    assert d.level("other") == 0.0
    d.release("other")
    d.step(0.2)
    assert d.level("other") == pytest.approx(0.1) and not d.is_inhibited("other")


def test_goal_links_learning_rule_and_several_goals():
    d = Drives({"sound": DriveParams(learning_rate=0.3, extinction=0.5, min_weight=0.05)})
    for k in range(1, 5):
        w = d.link("sound", (3, 4))
        assert w == pytest.approx(1 - 0.7**k)
    d.set_level("sound", 0.9)
    d.reward("sound", (8, 9))
    assert d.level("sound") == 0.0
    assert d.links("sound") == pytest.approx({(3, 4): 1 - 0.7**4, (8, 9): 0.3})
    assert set(d.goals) == {(3, 4), (8, 9)}
    assert d.extinguish("sound", (8, 9)) == pytest.approx(0.15)
    assert d.extinguish("sound", (8, 9)) == pytest.approx(0.075)  # still >= min_weight
    assert d.extinguish("sound", (8, 9)) == 0.0 and (8, 9) not in d.links("sound")
    assert d.extinguish("sound", (1, 1)) == 0.0  # no link: nothing to weaken


def test_extinction_drops_weak_links():
    d = Drives({"s": DriveParams(learning_rate=0.2, extinction=0.5, min_weight=0.06)})
    d.link("s", (1, 2))
    assert d.extinguish("s", (1, 2)) == pytest.approx(0.1)
    assert d.extinguish("s", (1, 2)) == 0.0 and d.links("s") == {}
    v = d.links_version
    d.unlink("s", (1, 2))
    assert d.links_version == v


def test_links_version_and_prune():
    d = Drives(["a"])
    v = d.links_version
    d.link("a", (1, 2))
    d.link("a", (2, 3))
    assert d.links_version == v + 2
    assert d.prune([(1, 2)]) == 1 and d.links("a").keys() == {(1, 2)}


def test_unknown_drive_and_bad_parameters():
    d = Drives(["sound"])
    for call in (lambda: d.level("food"), lambda: d.satisfy("food"),
                 lambda: d.link("food", (1, 2)), lambda: d.step(0.1, inhibited={"food"}),
                 lambda: d.inhibit("food")):
        with pytest.raises(KeyError, match=r"unknown drive 'food'.*'sound'"):
            call()
    with pytest.raises(ValueError, match="already exists"):
        d.add("sound")
    with pytest.raises(ValueError, match="non-empty string"):
        d.add("")
    with pytest.raises(ValueError, match="epsilon"):
        DriveParams(epsilon=-1)
    with pytest.raises(ValueError, match="learning_rate"):
        DriveParams(learning_rate=0)
    with pytest.raises(ValueError, match="initial"):
        DriveParams(initial=1.5)
    with pytest.raises(ValueError, match="epsilon\\*dt"):
        Drives({"fast": DriveParams(epsilon=20)}).step(0.1)
    with pytest.raises(ValueError, match="dt"):
        d.step(-0.1)
    with pytest.raises(ValueError, match="reward"):
        d.link("sound", (1, 2), reward=2.0)
    with pytest.raises(ValueError, match="transition"):
        d.link("sound", 5)


def test_save_and_load(tmp_path):
    d = Drives({"a": DriveParams(epsilon=0.2), "b": DriveParams(learning_rate=0.9)})
    d.set_level("a", 0.4)
    d.link("b", (5, 6))
    d.inhibit("a")
    e = Drives.load(d.save(tmp_path / "drives.json"))
    assert e.levels == d.levels and e.links("b") == d.links("b")
    assert e.params("a") == d.params("a") and e.is_inhibited("a")


def test_a_link_that_falls_exactly_to_min_weight_is_kept():
    # "links weaker than min_weight are dropped": 0.5 -> 0.25 = min_weight stays (exact floats)
    d = Drives({"s": DriveParams(learning_rate=0.5, extinction=0.5, min_weight=0.25)})
    d.link("s", (1, 2))
    assert d.extinguish("s", (1, 2)) == 0.25 and d.links("s") == {(1, 2): 0.25}
    assert d.extinguish("s", (1, 2)) == 0.0 and d.links("s") == {}


def test_unlink_and_prune_each_count_one_change_and_prune_counts_its_drops():
    d = Drives(["a", "b"])
    for t in [(1, 2), (2, 3), (3, 4)]:
        d.link("a", t)
    d.link("b", (2, 3))
    v = d.links_version
    d.unlink("a", (1, 2))
    assert d.links_version == v + 1  # one change, as for link (the planner re-propagates)
    assert d.prune([(3, 4)]) == 2  # a's and b's links to (2, 3)
    assert d.links_version == v + 2
    assert d.links("a") == {(3, 4): 0.5} and d.links("b") == {}
    assert d.prune([(3, 4)]) == 0 and d.links_version == v + 2  # nothing dropped, no change


def test_drives_is_a_container_of_its_names():
    d = Drives(["sound", "colour"])
    assert "sound" in d and "food" not in d
    assert list(d) == ["sound", "colour"] == d.names and len(d) == 2


def test_a_partial_reward_scales_the_link_step():
    # W += alpha * reward * (1 - W): alpha 0.5, reward 0.5 -> 0.25
    d = Drives({"s": DriveParams(learning_rate=0.5)})
    d.set_level("s", 0.8)
    d.reward("s", (1, 2), reward=0.5)
    assert d.links("s") == {(1, 2): 0.25} and d.level("s") == 0.0


def test_from_dict_names_what_is_wrong():
    good = Drives(["s"]).to_dict()
    with pytest.raises(ValueError, match=r"format 'nope'"):
        Drives.from_dict({**good, "format": "nope"})
    with pytest.raises(ValueError, match=r"format 'list'"):
        Drives.from_dict([good])
    with pytest.raises(ValueError, match=r"'drives' must be a list, got dict"):
        Drives.from_dict({**good, "drives": {}})
    item = good["drives"][0]
    with pytest.raises(ValueError, match=r"links of drive 's' must be a list"):
        Drives.from_dict({**good, "drives": [{**item, "links": {}}]})
    with pytest.raises(ValueError, match=r"link weight must lie in \[0.0, 1.0\]"):
        Drives.from_dict({**good, "drives": [{**item, "links": [[1, 2, 1.5]]}]})
    back = Drives.from_dict({**good, "drives": [{**item, "links": [[1, 2, 1.0]]}]})
    assert back.links("s") == {(1, 2): 1.0}


def test_a_zero_step_changes_nothing_and_a_bad_dt_is_named():
    d = Drives({"s": DriveParams(epsilon=0.5, initial=0.3)})
    d.step(0.0)
    assert d.level("s") == 0.3
    with pytest.raises(ValueError, match=r"^dt\b"):
        d.step(-0.1)
    with pytest.raises(ValueError, match=r"epsilon\*dt = 1.5 > 1 .*use a smaller dt$"):
        d.step(3.0)


def test_a_step_too_long_for_one_drive_changes_no_level():
    d = Drives({"a": DriveParams(epsilon=0.1), "b": DriveParams(epsilon=10.0)})
    d.inhibit("b")  # an inhibited drive is held at 0, never stepped: no check
    d.step(0.2)
    assert d.levels == pytest.approx({"a": 0.02, "b": 0.0})
    d.release("b")
    d.set_level("a", 0.3)
    with pytest.raises(ValueError, match=r"epsilon\*dt = 2 > 1 for drive 'b'"):
        d.step(0.2)
    assert d.levels == {"a": 0.3, "b": 0.0}  # 'a' (stepped first) did not move
    with pytest.raises(ValueError, match="for drive 'b'"):
        d.step(0.2, inhibited=["a"])
    assert d.levels == {"a": 0.3, "b": 0.0}  # nor was it held at 0

"""The experimenter's rules on hand-made observations (a stand-in teacher counts the sounds):
the stop in the zone, the delay exactly on its edge (within 1e-9 s) and one step short,
extinction and reset; the patrol lesson's order grown by hand-worked chains."""

from __future__ import annotations

import numpy as np

from hippo.tasks.teaching import Experimenter, lessons_again
from hippo.types import Observation


class _Teacher:
    def __init__(self) -> None:
        self.sounds = 0

    def sound(self) -> None:
        self.sounds += 1


def _obs(t: float, floor: int = 1, moving: bool = False) -> Observation:
    return Observation(t=t, tick=0, ir=np.zeros(8), floor=floor, sound=False,
                       odometry=np.zeros(3), moving=moving)


def test_the_sound_comes_once_the_robot_has_been_still_in_the_zone_for_the_delay():
    teacher = _Teacher()
    ex = Experimenter(teacher, delay=1.0)
    assert (ex.colour, ex.rewarding, ex.sounded, ex.still_since) == (1, True, False, None)
    assert ex(_obs(0.5)) is False and ex.still_since == 0.5      # the stop starts at 0.5 s
    assert ex(_obs(1.0)) is False and teacher.sounds == 0
    # 1 s after 0.5 s less 2e-9 s is short of the delay (tolerance 1e-9 s): no sound
    ex(_obs(1.5 - 2e-9))
    assert teacher.sounds == 0 and not ex.sounded and ex.still_since == 0.5
    # within the tolerance: the sound, once; returns False all the same
    assert ex(_obs(1.5 - 0.5e-9)) is False
    assert teacher.sounds == 1 and ex.sounded
    ex(_obs(2.0))
    ex(_obs(9.0))
    assert teacher.sounds == 1


def test_a_stop_out_of_the_zone_or_a_move_restarts_the_count():
    teacher = _Teacher()
    ex = Experimenter(teacher, delay=1.0, colour=2)
    ex(_obs(0.0, floor=2))
    ex(_obs(0.8, floor=1))                 # another colour: the stop in the zone ends
    assert ex.still_since is None
    ex(_obs(1.0, floor=2))
    assert ex.still_since == 1.0
    ex(_obs(1.2, floor=2, moving=True))    # moving in the zone: not a stop
    assert ex.still_since is None
    ex(_obs(1.4, floor=2))
    ex(_obs(2.2, floor=2))                 # 0.8 s since 1.4: not yet
    assert teacher.sounds == 0 and ex.still_since == 1.4
    ex(_obs(2.4, floor=2))                 # 1.0 s since 1.4
    assert teacher.sounds == 1


def test_extinction_withholds_the_sound_and_reset_starts_a_new_trial():
    teacher = _Teacher()
    ex = Experimenter(teacher, delay=0.0)
    ex.reset(rewarding=False)
    assert ex.rewarding is False
    ex(_obs(0.0))
    ex(_obs(5.0))
    assert teacher.sounds == 0 and not ex.sounded and ex.still_since == 0.0
    ex.reset()                             # rewarding kept when not given
    assert ex.rewarding is False and ex.still_since is None and not ex.sounded
    ex.reset(rewarding=True)
    ex(_obs(6.0))                          # delay 0: at once
    assert teacher.sounds == 1 and ex.sounded
    ex.reset()
    assert ex.rewarding is True and not ex.sounded and ex.still_since is None
    ex(_obs(7.0))
    assert teacher.sounds == 2             # a new trial sounds again


def test_lessons_again_appends_the_chain_up_to_the_failed_one_but_the_pending_ones():
    # chain 0 -> 1 -> 2 -> 3 -> 0; checkpoint 1 (position 1) needed the leash: 1 again,
    # nothing pending after position 1 is 1
    order, again = [0, 1, 2, 3, 0], set()
    lessons_again(order, 1, again)
    assert order == [0, 1, 2, 3, 0, 1] and again == {1}
    # checkpoint 3 (position 3): the chain 1, 2, 3 less the pending 0, 1 after position 3
    lessons_again(order, 3, again)
    assert order == [0, 1, 2, 3, 0, 1, 2, 3] and again == {1, 3}
    # the first checkpoint at its second place (position 4): nothing, nothing noted
    lessons_again(order, 4, again)
    assert order == [0, 1, 2, 3, 0, 1, 2, 3] and again == {1, 3}
    # checkpoint 2 failing in the repeats (position 6): 1, 2 again, less the pending 3
    lessons_again(order, 6, again)
    assert order == [0, 1, 2, 3, 0, 1, 2, 3, 1, 2] and again == {1, 2, 3}


def test_lessons_again_takes_the_chain_up_to_the_first_checkpoint_coming_back():
    # the route's order is 5, 3, 4 (numbers are not positions); 4 failed: 3, 4 again
    order, again = [5, 3, 4, 5], set()
    lessons_again(order, 2, again)
    assert order == [5, 3, 4, 5, 3, 4] and again == {4}
    # the first checkpoint's own failure changes nothing, at either place
    order, again = [5, 3, 4, 5], set()
    lessons_again(order, 0, again)
    lessons_again(order, 3, again)
    assert order == [5, 3, 4, 5] and again == set()


def test_the_delay_counts_as_reached_exactly_at_its_tolerance():
    # still since 0.0: at t = 1.0 - 1e-9, t - 0.0 is the very float delay - 1e-9
    teacher = _Teacher()
    ex = Experimenter(teacher, delay=1.0)
    ex(_obs(0.0))
    ex(_obs(1.0 - 1e-9))
    assert teacher.sounds == 1


def test_lessons_again_by_the_rule_on_hand_made_orders():
    # "the lessons of the chain from c1 up to the failed one, but for those already pending
    # after at": 3 fails at position 5 with 1 pending right after it: 2, 3
    order: list[int] = [0, 1, 2, 3, 0, 3, 1]
    lessons_again(order, 5, set())
    assert order == [0, 1, 2, 3, 0, 3, 1, 2, 3]
    # 1 fails at the end: 1 only, not the chain's next (2)
    order = [0, 1, 2, 3, 0, 1]
    lessons_again(order, 5, set())
    assert order == [0, 1, 2, 3, 0, 1, 1]

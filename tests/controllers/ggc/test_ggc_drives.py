"""GGC on robots whose drive must turn (issue 69): the robot next in line to leave its
formation faces its way out while it waits when it cannot back up (kilobot); a holonomic or
diff robot rests as before (the golden hashes in tests/engine pin whole holonomic runs)."""

import math

import numpy as np

from controllers.ggc import GGCParams
from controllers.ggc.rules.detection import FACE_CRAWL
from controllers.ggc.statuses import COVERAGE, DETECTION
from controllers.ggc.swarm import rule_params
from tests.ggc_bot import Bot

TURN = 0.325
"""A kilobot's turn rate in place, rad/tick (kilobot_turn)."""


def test_only_robots_that_must_turn_round_face_their_way_out():
    def faces(turn_rate: float, reverse: bool) -> bool:
        return rule_params(GGCParams(), 3, False, turn_rate, reverse).face_to_leave

    assert not faces(math.inf, True)  # holonomic
    assert not faces(TURN, True)  # diff: backs out, never more than a quarter turn
    assert faces(TURN, False)  # kilobot


def _next_in_line(turn_rate: float, reverse: bool = False) -> np.ndarray:
    """A waiting robot (gradient 2) beside its formation neighbour (gradient 1, one unit to
    +x) while a mover of its group that outranks it (gradient 3) is still within d_cover:
    its velocity this tick."""
    bot = Bot(status=DETECTION, turn_rate=turn_rate, reverse=reverse)
    bot.me["gradient"] = 2
    rows = [((1.0, 0.0), 3, 1, DETECTION), ((0.0, 3.0), 9, 1, COVERAGE)]
    return bot.step(rows, gradient=[1, 3]).velocities[0]


def test_a_robot_next_in_line_faces_its_way_out_with_a_turning_drive_and_rests_without():
    assert np.allclose(_next_in_line(math.inf, True), 0.0)  # holonomic: rests, as before
    assert np.allclose(_next_in_line(TURN, True), 0.0)  # diff: rests too
    wish = _next_in_line(TURN)
    assert np.isclose(np.hypot(*wish), GGCParams().v * FACE_CRAWL)  # it barely moves
    assert wish[0] < 0.0  # away from its neighbour, as edge-following at d_cover begins

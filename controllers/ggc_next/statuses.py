"""GGC's statuses (paper Figures 3, 6 and 7) and the commands relayed through a formation."""

INITIAL, DETECTION, COVERAGE, ARRIVE, STOP, APPROACH, PEND, JOIN, FORMED, SURPLUS = range(10)
STATUSES = ("Initial", "Detection", "Coverage", "Arrive", "Stop", "Approach", "Pend", "Join",
            "Formed", "Surplus")
"""Names by status number. Formed is the paper's aggregation Arrive (in a group's formation,
waiting to travel); Arrive is the coverage Arrive (stopped on the target for good). Surplus
(our addition): stopped for good off the target, because the group's structure has no place
left (see GGCParams.surplus_stop)."""
SETTLED = ("Arrive", "Surplus")
"""Statuses of robots done and standing still for good."""
MOVING_STATUSES = (COVERAGE, APPROACH, JOIN)
"""Statuses in which a robot moves on purpose (broadcast as ``moving``)."""
GATHERING = (APPROACH, PEND, JOIN)
"""Aggregation statuses of a robot not yet in its group's formation."""
CMD_NONE, CMD_TRAVEL, CMD_HALT = 0, 1, 2

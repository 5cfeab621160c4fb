"""GGC parameters: the paper's Table 2 plus the constants its algorithms leave open.

What each of our additions was measured to do is in docs/reports/ggc-findings-journal.md.
"""

from __future__ import annotations

from dataclasses import dataclass

from swarmsim.controller import require_non_negative, require_positive

from .rules.rulesets import DEFAULT_RULESET, RULESETS


@dataclass(frozen=True)
class GGCParams:
    """Parameters of the GGC controller (lengths in units, times in ticks).

    Attributes:
        d_safe: safe distance between robots (paper Table 2: 1).
        d_cover: coverage distance, the spacing robots keep when they stop (Table 2: 1, 2, 4,
            6, 8, 10; default 6).
        d_min: spacing of a formation; gradients form among neighbours within d_min * 1.5
            (Algorithm 1; default d_safe = 1).
        R_c: communication range: robots hear broadcasts within it (Table 2: 15).
        v: speed (Table 2: 0.1 per tick).
        gradient_reach: robots sense at least gradient_reach * d_cover (the sensing range is
            the largest of R_c, this and d_cover + 2).
        radial_gain: edge following: radial correction per unit of distance error.
        arrive_tolerance: a robot beside an arrived robot stops once it is at least
            d_cover - arrive_tolerance from it.
        probe_distance: the floor probe looks this far ahead (Algorithm 2: one unit).
        yield_distance: a moving robot waits while another moving robot with a larger id is
            this close ahead (and backs away within 0.75 of it).
        orbit: +1 follows edges counter-clockwise around the nearest robot, -1 clockwise. With
            groups, a group whose formation travelled (d_x, d_y) with d_x * d_y > 0 orbits
            -orbit, the others orbit (our addition; the paper does not say).
        T_r: progress is sampled every T_r ticks (Section 4.4, Equation 3).
        theta: moving less than theta in T_r ticks is a deadlock (Equation 3).
        T_s: a robot stopped by a deadlock waits T_s ticks before it resumes (Algorithm 6).
        init_timeout: a robot that has heard no gradient after this many ticks starts with an
            infinite gradient (it may be isolated or its neighbours may have failed).
        h_max: leader hand-over hop budget (Algorithm 3).
        handover_reach: a leader hands over only to a neighbour this close (the paper allows
            any neighbour within R_c).
        T_settle: scattered start: ticks between leader hand-overs.
        T_quiet: scattered start: a group's formation leaves for the target once none of its
            robots has heard a robot of the group that is still gathering for this many ticks.
        aggregation_timeout: scattered start: a robot not in its formation this many ticks
            after leader selection covers on its own.
        join_tolerance: a joining robot takes its place in the formation when two formed
            robots are within d_min + join_tolerance.
        boundary_probe: with one group (with groups, under the HOLES rules, once it has walked
            a while), an edge-follower just outside the target that senses
            target floor this far toward an arrived robot steps in and stops on the boundary
            (boundary fill, our addition); also how far outward the surplus lap looks for free
            target floor. At most the engine's probe range.
        lattice_stop: with one group, rule (b) also needs a second arrived robot within
            d_cover + arrive_tolerance, so that robots stop on lattice sites (our addition;
            only while d_cover + arrive_tolerance <= lattice_reach). Between groups rule (b)
            always needs it (robots where two groups meet close triangles).
        lattice_reach: r * sqrt(3) for the paper's coverage radius r = 4: the longest
            triangle side that discs of radius r still cover.
        yield_release: a wedged robot back in Detection waits for a robot around it to leave
            first; while d_cover <= yield_release (0: never) it stops waiting once every
            waiting robot around it is yielding or enclosed too and it is on the formation's
            outside. The same bound makes a stuck robot outside the target rejoin its formation
            from 1.5 d_min away (with groups at any d_cover), and a mover that went round an
            island off the target (a formation halted off it) leave it for the beacon
            (rules/island.py).
        confined_ticks: under the rule set's SURPLUS flag and while d_cover <= yield_release
            (where the surplus lap does not apply), a mover that has spent this many ticks
            in Coverage and Stop (at d_cover = d_safe; in proportion to d_safe + d_cover:
            the reach, and the walk round it, grow with d_cover) without getting farther
            than confined_reach from where the count started, and without hearing more
            arrived robots than it did when the count started, stops for good (our
            addition; Arrive on the target, else Surplus; rules/confined.py). Getting
            farther, or hearing the structure grow, starts the count again; hearing robots
            of its own group still waiting to be sent pauses it.
        confined_reach: see confined_ticks (multiples of d_cover; the mover's own odometry
            measures it).
        confined_walk: under the same flag and bound, a mover in Coverage that has walked
            more than confined_walk * d_cover * max(d_cover, 2 d_safe) / d_safe units since it
            left its formation gives up as a confined one does (our addition; a walk along
            the structure restarts the count of confined_ticks whenever it hears more
            arrived robots, so the count alone lets such a mover walk for ever; the places
            lie d_cover apart, so the walk a search needs grows faster than d_cover).
        surplus_stop: with one group (with groups, under the rule set's SURPLUS flag where
            holes are not filled) and d_cover > yield_release, surplus robots stop (our addition; False: the paper's
            robots circle on; rules/surplus.py). A mover that has been out of
            hearing of its group's waiting robots and comes back beside them (within d_cover
            + arrive_tolerance) after a lap that went round the beacon (surplus_winding) and
            walked at most surplus_frontier units on the target with target floor outward
            stops for good, as Surplus (Arrive if on the target). A waiting robot of the
            group that hears a Surplus robot of its group within d_cover + arrive_tolerance
            stays as Surplus, and a mover that reaches one stops too. With groups, a whole
            turn round the beacon without passing free target floor is a lap too, and a
            mover walled in by arrived robots on the target stops there.
        surplus_frontier: see surplus_stop (units of path).
        surplus_winding: see surplus_stop (degrees the bearing to the beacon must turn).
        surplus_spread: with surplus_stop, a mover off the target that hears a Surplus robot
            of its group (with groups: of any group) stops as Surplus too.
        ruleset: which of our rules beyond the paper's apply (rules/rulesets.py):
            "yield-holes" (default): no Stop between groups (movers of all groups give way
            to a larger-id mover close ahead, as movers of one group do), movers fill
            holes sealed inside the structure (rules/holes.py), surplus movers of every
            group stop once the target is full (at d_cover 8 and 10; rules/surplus.py), or,
            at d_cover <= yield_release, once they stay confined without a place
            (confined_ticks, confined_walk; rules/confined.py), and a formation halts where
            it meets another group's halted formation that reached the target (flag BESIDE,
            rules/travel.py);
            "paper": the paper's rules
            (Section 4.3: a mover stops while another group's mover in Coverage with a
            larger id is within d_cover); "yield" and "paper-holes": one of the two;
            "yield-holes-push": the default without BESIDE (formations push into each
            other), as the default was before BESIDE joined it;
            "yield-holes-cross" (experimental): yield-holes-push, and a mover walled in
            beside its formation crosses the structure toward the beacon (rules/cross.py);
            "yield-holes-aside" (experimental): yield-holes-push, and a formation that meets
            another group's robots on its way turns aside along them (rules/aside.py);
            "yield-holes-trains" (experimental): yield-holes, and formations release their
            robots as trains, each leaving once the mover ahead of it on its way out is a
            train gap away instead of d_cover (rules/trains.py).
            "flow" (experimental): yield-holes, and movers walk through the structure and
            settle at the first free lattice site they meet (rules/flow.py).
    """

    d_safe: float = 1.0
    d_cover: float = 6.0
    d_min: float = 1.0
    R_c: float = 15.0
    v: float = 0.1
    gradient_reach: float = 1.3
    radial_gain: float = 1.0
    arrive_tolerance: float = 0.3
    probe_distance: float = 1.0
    yield_distance: float = 2.0
    orbit: int = 1
    T_r: int = 100
    theta: float = 1.0
    T_s: int = 100
    init_timeout: int = 400
    h_max: int = 5
    handover_reach: float = 8.0
    T_settle: int = 40
    T_quiet: int = 200
    aggregation_timeout: int = 5000
    join_tolerance: float = 0.15
    boundary_probe: float = 2.0
    surplus_stop: bool = True
    surplus_frontier: float = 2.0
    surplus_winding: float = 270.0
    surplus_spread: bool = True
    yield_release: float = 4.0
    confined_ticks: float = 3000.0
    confined_reach: float = 6.0
    confined_walk: float = 75.0
    lattice_stop: bool = True
    lattice_reach: float = 6.93
    ruleset: str = DEFAULT_RULESET

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "d_cover", "d_min", "R_c", "v", "gradient_reach", "radial_gain",
                    "probe_distance", "yield_distance", "T_r", "T_s", "init_timeout", "T_settle",
                    "T_quiet", "aggregation_timeout", "join_tolerance", "handover_reach",
                    "boundary_probe", "confined_ticks", "confined_reach", "confined_walk")
        if self.d_cover < self.d_safe:
            raise ValueError(f"d_cover ({self.d_cover}) must be >= d_safe ({self.d_safe})")
        if self.orbit not in (1, -1):
            raise ValueError(f"orbit must be 1 or -1, got {self.orbit!r}")
        if self.ruleset not in RULESETS:
            raise ValueError(f"ruleset must be one of {', '.join(RULESETS)}, got "
                             f"{self.ruleset!r}")
        require_non_negative(self, "theta", "arrive_tolerance", "h_max", "yield_release",
                             "surplus_frontier", "surplus_winding")
        if self.h_max > 127:  # broadcast as int8
            raise ValueError(f"GGC parameter h_max must be <= 127, got {self.h_max!r}")
        if self.theta > 2 * self.d_cover:
            raise ValueError(f"theta ({self.theta}) must not exceed 2 * d_cover (Section 4.4)")

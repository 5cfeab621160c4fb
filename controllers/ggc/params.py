"""GGC parameters: the paper's Table 2 plus the constants its algorithms leave open."""

from __future__ import annotations

from dataclasses import dataclass

GROUP_ORBITS = ("away", "alternate", "same")
JUNCTION_STOPS = ("always", "lattice", "never")
BOUNDARY_FILLS = ("one-group", "always", "never")
CHOICES = {"group_orbit": GROUP_ORBITS, "junction_stop": JUNCTION_STOPS,
           "boundary_fill": BOUNDARY_FILLS}
"""The parameters that take one of a few named rules, with their rules."""
BOOLEAN_FILLS = {"true": "always", "false": "never"}
"""boundary_fill was a bool: true and false still mean "always" and "never"."""


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
            the largest of R_c, this and d_cover + 2; with R_c = 15 it matters only for
            d_cover > 11). A mover's gradient is its nearest stationary robot's plus one (with
            groups: its own group's nearest within 1.5 d_cover), whatever this value
            (Algorithm 2, line 8; see coverage.py, follow_gradient).
        radial_gain: edge following: radial correction per unit of distance error.
        arrive_tolerance: a robot beside an arrived robot of its gradient stops once it is at
            least d_cover - arrive_tolerance from it.
        probe_distance: the floor probe looks this far ahead (Algorithm 2: one unit).
        yield_distance: a moving robot waits while another moving robot is this close ahead.
        orbit: +1 follows edges counter-clockwise around the nearest robot, -1 clockwise.
        group_orbit: with groups, the sense each group's movers orbit in (our addition; the
            paper does not say). "away" (default): a group whose formation travelled (d_x, d_y)
            to the target with d_x * d_y > 0 orbits -orbit, the others orbit. With orbit +1
            and formations coming from below or above the beacon, a group that came from its
            left sends its movers further left first, and one from its right further right. Each
            robot reads it off the travel command its formation followed (its gradient
            parent's vx, vy), so no new message is needed; a robot that never travelled
            keeps orbit. Groups then enter the structure's edge by different routes instead
            of merging into one stream. "alternate": odd groups orbit, even groups -orbit.
            "same": every group orbit (the rule before). K, 3 groups, seeds 0-2, coverage at
            tick 12,000: 0.855, 0.864, 0.821 with "away" (and "alternate", which gave the
            same senses on these seeds) against 0.750, 0.626, 0.702 with "same".
        T_r: progress is sampled every T_r ticks (Section 4.4, Equation 3).
        theta: moving less than theta in T_r ticks is a deadlock (Equation 3).
        T_s: a robot stopped by a deadlock waits T_s ticks before it resumes (Algorithm 6).
        init_timeout: a robot that has heard no gradient after this many ticks starts with an
            infinite gradient (it may be isolated or its neighbours may have failed).
        h_max: leader hand-over hop budget (Algorithm 3).
        handover_reach: a leader hands over only to a neighbour this close (units). The paper
            allows any neighbour within R_c; the hand-over then favours the swarm's far edges,
            and leaders there get small groups (Algorithm 4 splits the swarm by nearness).
        T_settle: scattered start: ticks between leader hand-overs (the leaders' distance
            fields settle meanwhile; they are refreshed this often).
        T_quiet: scattered start: a group's formation leaves for the target once none of its
            robots has heard a robot of the group that is still gathering for this many ticks.
        aggregation_timeout: scattered start: a robot not in its formation this many ticks
            after leader selection covers on its own.
        join_tolerance: a joining robot takes its place in the formation when two formed
            robots are within d_min + join_tolerance (units).
        boundary_fill: an edge-follower just outside the target that senses target floor
            within boundary_probe toward an arrived robot steps in and stops on the boundary
            (our addition: fills the strip the paper's rules leave between the last row of
            robots and the boundary). "one-group" (default): only with one group; "always";
            "never" (true and false are taken for "always" and "never"). With groups it sealed
            holes: movers of two groups stepped in along both edges of K's upper arm and the
            rows met at its tip round an empty middle that no mover reached for thousands of
            ticks. K, 3 groups, seeds 0-4, with junction_stop "lattice": all complete, at
            ticks 25,063 / 17,157 / 17,135 / 21,303 / 18,578 (mean 19,847) without it, against
            27,787 / - (0.986 by the plateau at 30,406) / 25,488 / 27,401 / 33,849 with it.
            In 'corridor' (2 groups) it no longer helps: mean coverage 0.970 with it (seeds
            0-5), 0.977 without (seeds 0-4).
        boundary_probe: see boundary_fill, units (<= the engine's probe range, 2).
        lattice_stop: rule (b) also needs a second arrived robot within d_cover +
            arrive_tolerance, so that robots stop on lattice sites and leave no holes between
            three robots (our addition: without it K seed 4 and house seed 4 end at 0.986 and
            0.987 with small holes). Applies only while d_cover + arrive_tolerance <=
            lattice_reach: beyond it a lattice cannot close the holes anyway. One group only:
            with two groups in 'corridor' it left more movers meeting (1,304 collision stops
            instead of 87) and ended at 0.974 instead of 0.980; on K (3 groups, seed 1) it
            had 0.966 at tick 27,000 against 0.986 at 21,000 without it. Between groups
            junction_stop does the same job. Tried again with groups under today's rules
            (junction_stop "lattice", boundary fill for one group), K 3 groups: seeds 0-2
            complete at ticks 20,630 / 30,377 / 16,605 against 25,063 / 17,157 / 17,135
            without it, and seed 3 had not completed by 28,000 (21,303 without): no better.
        lattice_reach: r * sqrt(3) for the paper's coverage radius r = 4 (units): the longest
            triangle side that discs of radius r still cover.
        follow_other_formations: with groups, movers follow the edges of other groups' waiting
            formations too (the paper's rule). False (default): only their own group's
            robots and arrived robots of any group, so that a group's movers do not wander
            round another group's formation into that group's stream. K, 3 groups, seeds
            0-2, coverage at tick 12,000: 0.641, 0.571, 0.820 against 0.639, 0.583, 0.637
            with the paper's rule (experiments/ggc-groups-rules.toml).
        stop_ahead_only: Section 4.3's Stop only for another group's mover ahead of me (in my
            direction of travel), not one behind or beside me (experimental).
        stop_on_target_only: Section 4.3's Stop only on the target; off it, movers of other
            groups pass each other with give_way alone (experimental, default False: the
            paper's rule everywhere). With ten groups on the large K, hundreds of movers stand
            in Stop outside the target. K, 3 groups, seed 0, coverage at tick 12,000: 0.932
            against 0.855, but to the end seed 0 stops at 0.971 by the plateau (tick 34,606)
            where the default completes, and seed 3 at 0.973 (tick 51,400; default 0.975);
            K-large at tick 5,000: 0.239 against 0.265 (movers that no longer stop beside
            their formation hold its waiting robots back longer).
        stop_patience: a robot in Stop (Section 4.3) off the target that has waited this
            many ticks while another group's mover is still within d_cover goes on, and does
            not Stop for other groups for the next T_s ticks (experimental; 0, the default: it
            waits as long as the mover is there, the paper's rule). On the target it always
            waits. With ten groups on the large K, hundreds of robots wait in Stop outside the
            target for movers jammed in the same crowd. With 500, K, 3 groups, seeds 0-4
            complete at 14,630 / 16,040 / 26,662 / 14,085 / 17,094 (mean 17,702) with
            211,668 / 213,061 / 326,936 / 193,147 / 225,137 moved (mean 233,990), against
            18,537 / 17,157 / 14,863 / 13,784 / 18,578 (16,584) and 245,881 / 230,636 /
            205,262 / 183,117 / 239,097 (220,799) by default: better on three seeds, but
            seed 2 left a hole inside the upper arm (0.984 at tick 20,000). house, seeds 0-4:
            mean completion 42,150 against 35,321 (faster on seed 0 only). The large K, seed
            0: 0.728 at tick 45,000, still rising slowly, where the default stays at 0.672
            from tick 38,000. Applied on the target too (the option's first form) it was
            worse on K (seeds 0-2 completed at 21,185 / 15,563 / 26,997), and the large K
            reached 0.731 at 45,000.
        yield_release: a wedged robot back in Detection waits for a robot around it to leave
            first (``yield_count``); while d_cover <= yield_release (units; 0: never) it stops
            waiting once every waiting robot around it is yielding or enclosed too and it is
            on the formation's outside (our addition: without it, at d_cover 2 on K the whole
            rim ends up yielding to itself and 287 robots never leave the formation). The
            bound keeps d_cover 6 runs as they were: there the rule fires twice in K's first
            2,500 ticks (one group, seed 0) and changes the run, though it never deadlocked.
            The same bound widens ``wedged`` (collisions.py): a robot stuck outside the target
            rejoins its formation from 1.5 d_min away, not only when touching it (with groups
            at any d_cover).
        spaced_deadlock_arrive: with groups, a deadlocked mover on the target arrives only at
            d_cover - arrive_tolerance from its nearest stationary robot, else it Stops for
            T_s (our earlier rule). False (default): it arrives where it is when a robot in
            Stop is within hearing, as the paper's Algorithm 5 says. The paper's rule packs
            some robots closer but clears jams: K, 3 groups, seeds 0-2, coverage at tick
            12,000 0.639, 0.583, 0.637 against 0.600, 0.597, 0.610 with the spacing rule.
            On the large K (seed 0) the spacing rule does better: 0.765 at tick 45,000 where
            the default stays at 0.672 (no dense line of arrived robots along the leg's inner
            edge). On K with 3 groups it does worse: seeds 0 / 2 complete at 23,582 / 19,232
            (default 18,537 / 14,863) and seed 1 ends by the plateau at 0.985 (tick 34,001).
        surplus_stop: surplus robots stop (our addition; False: the paper's robots circle on).
            A mover that has been out of hearing of its group's waiting robots and comes back
            beside them (its nearest stationary robot is a waiting robot of its group, within
            d_cover + arrive_tolerance) has gone round its group's structure. If on the way
            it walked at most surplus_frontier units on the target with target floor outward
            too (boundary_probe units away from the structure), there is no place left that
            it can find: it stops for good, as Surplus (Arrive if on the target). Otherwise
            it goes round again. Only while d_cover > yield_release: at smaller d_cover movers
            weave through the formation's jams and come back beside it after short walks
            (small world, d_cover 1: coverage 0.18 fell to 0.10 with the rule). One group
            only: with groups, movers come home round other groups' structures and the
            formations stopped early (K, 3 groups, seed 0, coverage at tick 12,000: 0.613
            against 0.750 without the rule). A waiting robot of the group that hears a
            Surplus robot of its group within d_cover + arrive_tolerance stays where it is
            as Surplus, so the whole formation stops, and movers that reach a Surplus robot
            of their group stop there too. The lap must also go round the beacon
            (surplus_winding). Turning round at a dead end forgets having been away. Without it, at
            d_cover 8 and 10 half of K's robots circle until the plateau rule ends the run,
            and the distance moved grows with d_cover instead of falling as in the paper's
            Figure 19.
        surplus_frontier: see surplus_stop (units of path).
        surplus_winding: with surplus_stop, a lap counts only if the bearing to the beacon
            turned by at least this much on the way (degrees): the lap went round the
            structure, which holds the beacon once the target is full, not just into a bay
            of its edge and back out beside the formation (K, d_cover 8, seed 3: a formation
            at the mouth of the bay under K's leg stopped at coverage 0.34, 100 robots on the
            target, after a 63-unit "lap"). Not checked in worlds without a beacon.
        surplus_spread: with surplus_stop, a mover off the target that hears a Surplus robot
            of its group stops as Surplus too, so that the news runs back along the stream of
            movers round the structure instead of each mover walking home first.
        junction_stop: rule (b) beside another group's arrived robot, whose gradient is not
            comparable with mine: "always" stop there (the rule before), "lattice" (default)
            only where a second arrived robot is within d_cover + arrive_tolerance, so that
            the robots where two groups meet close triangles instead of sealing holes between
            the groups' lattices, "never" (experimental). K, 3 groups: seed 0 completes at
            tick 27,787 with 330,117 moved against 50,226 and 508,515 with "always"; seed 1
            ends at 0.986 by the plateau at tick 30,406 (340,935 moved) against 0.984 at
            47,675 (488,105).
        own_edges: with groups, a mover outside the target that reaches another group's
            structure turns back, so that each group keeps to its own part of the swarm's edge
            (experimental, off by default).
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
    group_orbit: str = "away"
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
    boundary_fill: str = "one-group"
    boundary_probe: float = 2.0
    own_edges: bool = False
    surplus_stop: bool = True
    surplus_frontier: float = 2.0
    surplus_winding: float = 270.0
    surplus_spread: bool = True
    yield_release: float = 4.0
    follow_other_formations: bool = False
    stop_ahead_only: bool = False
    stop_on_target_only: bool = False
    stop_patience: int = 0
    lattice_stop: bool = True
    spaced_deadlock_arrive: bool = False
    lattice_reach: float = 6.93
    junction_stop: str = "lattice"

    def __post_init__(self) -> None:
        positive = ("d_safe", "d_cover", "d_min", "R_c", "v", "gradient_reach", "radial_gain",
                    "probe_distance", "yield_distance", "T_r", "T_s", "init_timeout", "T_settle",
                    "T_quiet", "aggregation_timeout", "join_tolerance", "handover_reach")
        for name in positive:
            if not getattr(self, name) > 0:
                raise ValueError(f"GGC parameter {name} must be positive, got "
                                 f"{getattr(self, name)!r}")
        if self.d_cover < self.d_safe:
            raise ValueError(f"d_cover ({self.d_cover}) must be >= d_safe ({self.d_safe})")
        if self.orbit not in (1, -1):
            raise ValueError(f"orbit must be 1 or -1, got {self.orbit!r}")
        fill = str(self.boundary_fill).lower()
        object.__setattr__(self, "boundary_fill", BOOLEAN_FILLS.get(fill, self.boundary_fill))
        for name, rules in CHOICES.items():
            if getattr(self, name) not in rules:
                raise ValueError(f"{name} must be one of {', '.join(rules)}, got "
                                 f"{getattr(self, name)!r}")
        nonnegative = ("theta", "arrive_tolerance", "h_max", "yield_release", "surplus_frontier",
                       "surplus_winding", "stop_patience")
        for name in nonnegative:
            if getattr(self, name) < 0:
                raise ValueError(f"GGC parameter {name} must be >= 0, got "
                                 f"{getattr(self, name)!r}")
        if self.h_max > 127:  # broadcast as int8
            raise ValueError(f"GGC parameter h_max must be <= 127, got {self.h_max!r}")
        if self.theta > 2 * self.d_cover:
            raise ValueError(f"theta ({self.theta}) must not exceed 2 * d_cover (Section 4.4)")

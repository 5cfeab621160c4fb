"""Rule sets: which of our rules beyond the paper's a GGC run uses (``GGCParams.ruleset``).

A rule set is a name for a set of flags, the bits of one integer (``RuleParams.flags``);
each flag switches on the functions of one module:

* YIELD (rules/intergroup.py): no Section 4.3 Stop between groups. Movers of every group
  give way to each other as movers of one group do (coverage.give_way: a larger-id mover
  close ahead), so no robot is parked as structure for another group. A mover jammed
  against another group's formation beside its own waits with its own (deadlock.wedged).
* HOLES (rules/holes.py): arrived robots report holes sealed inside the structure (gaps in
  the lattice, and large holes the structure closed round), and
  movers that have walked a while without finding a place go and fill them, or step into a
  strip the structure leaves along the target's boundary (coverage.fills_boundary).
* SURPLUS (rules/surplus.py), with groups, at a d_cover whose lattice leaves holes by design
  (where HOLES does not apply): the surplus lap of one group applies, and more. A mover that
  went once round the structure (its bearing to the beacon turned a whole turn) without
  passing free target floor stops for good, as do a mover on the target walled in by arrived
  robots and a mover off the target that hears a Surplus robot of any group: the target is
  full, and the news spreads outward. So the robots the target cannot hold end standing
  instead of circling on. At d_cover <= yield_release, where the surplus lap does not apply,
  a mover that stays within a small reach for long without a place gives up instead
  (rules/confined.py).
* ASIDE (rules/aside.py), with groups: a formation in Initial whose front meets another
  group's robots turns at right angles to the beacon's bearing, away from them, and slides
  along them, instead of pushing its way through (which packs both formations until their
  robots touch, and keeps them awake in pymunk); a follower that lost its formation starts
  alone. Experimental: "yield-holes-aside" is not the default (docs/reports/ggc-findings-journal.md,
  "Formations that turn aside").
* BESIDE (rules/travel.py, ``touching``), with groups: a formation in Initial halts where its
  front meets a halted formation of another group that reached the target (its robots in
  Detection that say so) as if it had touched the target, so that no formation pushes
  into another. Part of the default; "yield-holes-push" is the default without it, as it
  was before (docs/reports/ggc-findings-journal.md, "Formations that halt beside another").
* CROSS (rules/cross.py): a mover walled in beside its own formation, that has walked far off
  the target without finding a place, crosses the structure toward the beacon, to the open
  floor beyond it. Experimental: "yield-holes-cross" is not the default
  (docs/reports/ggc-findings-journal.md, "The large K at 40,000 ticks").
* TRAINS (rules/trains.py): a formation releases its robots as trains. A waiting robot
  leaves as soon as the mover ahead of it along its way out (the edge's tangent in its orbit
  sense) is a train gap away (a few d_safe), not d_cover; robots that would leave in line,
  the one ahead by more than the gap, may leave together. Movers behind or beside its way
  out, and outranking waiting robots elsewhere within d_cover, still hold it (Algorithm 7).
  Experimental: "yield-holes-trains" is not the default (docs/reports/ggc-findings-journal.md,
  "Formations that release trains").
* THROUGH (rules/flow.py): movers walk through the structure (its bodies stand d_cover
  apart) toward free places, climbing their group's arrived robots' gradient, and settle at
  the first free lattice site they meet on the target (d_cover from two arrived robots, no
  robot nearer than d_cover - arrive_tolerance), instead of following its edge to its end;
  with no way through sensed they follow the edge as before. Experimental: rule set "flow"
  (docs/reports/ggc-findings-journal.md, "Walking through the structure").

* SOW (rules/sow.py): a formation does not halt where its front first touches the target;
  it walks on across the target toward the beacon, and its rear drops robots on the target
  about d_cover apart as it goes (the rearmost robot within d_cover with no settled robot
  near settles where it is), several across its width at once, none waiting for a turn or
  enclosed. It halts where its front reaches the target's far edge or another group's
  robots, or its leader passes the beacon, and releases the rest by Algorithm 7.
  Experimental: rule set "sow" (docs/reports/ggc-findings-journal.md, "Formations that sow
  robots as they cross the target").

Adding a rule set is an entry in RULESETS; adding a flag is a bit here, its scope in
FLAG_SCOPE and a branch where its rule applies. docs/reports/ggc-findings-journal.md has each
rule set's measurements.
"""

from __future__ import annotations

YIELD, HOLES, CROSS, SURPLUS, ASIDE, BESIDE, THROUGH, TRAINS, SOW = (
    1, 2, 4, 8, 16, 32, 64, 128, 256)
"""The flags."""
RULESETS = {
    "yield-holes": YIELD | HOLES | SURPLUS | BESIDE,
    "paper": 0,
    "yield": YIELD,
    "paper-holes": HOLES,
    "yield-holes-push": YIELD | HOLES | SURPLUS,
    "yield-holes-cross": YIELD | HOLES | SURPLUS | CROSS,
    "yield-holes-aside": YIELD | HOLES | SURPLUS | ASIDE,
    "yield-holes-trains": YIELD | HOLES | SURPLUS | BESIDE | TRAINS,
    "flow": YIELD | HOLES | SURPLUS | BESIDE | THROUGH,
    "sow": YIELD | HOLES | SURPLUS | BESIDE | SOW,
}
"""Rule set names and their flags. "paper": the paper's rules (Section 4.3's Stop between
groups, nothing reported about holes)."""
DEFAULT_RULESET = "yield-holes"
"""GGC's default rule set."""

ANY_GROUPS = "any groups"
"""A flag's scope: its rules act in a run of one group as in a run of several."""
BETWEEN_GROUPS = "between groups"
"""A flag's scope: its rules act only on another group's robots, so a run of one group is the
same run without the flag."""
FLAG_SCOPE = {
    YIELD: BETWEEN_GROUPS,  # intergroup.py answers as the paper does with one group;
    #                         deadlock.wedged reads YIELD only with groups
    HOLES: ANY_GROUPS,
    CROSS: ANY_GROUPS,
    SURPLUS: "yield_release",  # with one group the surplus lap follows surplus_stop alone;
    #                            the flag's confined movers act at d_cover <= yield_release
    ASIDE: BETWEEN_GROUPS,  # aside.blocked_side returns at once with one group
    BESIDE: BETWEEN_GROUPS,  # travel.touching halts only beside another group's formation
    TRAINS: ANY_GROUPS,  # trains.train_blockers releases robots of one group as of several
    THROUGH: ANY_GROUPS,
    SOW: ANY_GROUPS,  # sow.sows drops robots of one formation as of several
}
"""Where each flag's rules act: :data:`ANY_GROUPS`, :data:`BETWEEN_GROUPS`, or the name of a
GGCParams length L: between groups only while d_cover > L (with one group too at d_cover <=
L). Two rule sets whose flags differ only by flags that do not act in a run make the same
run, and share its run id (swarm.acting_flags): a rule that makes a flag act with one group
must change its scope here."""

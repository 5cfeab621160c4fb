"""GGC's rules, each written once as a compiled (numba) function of one robot's view.

A rule sees its own robot's state row (``me``, a record of state.STATE_DTYPE), its
neighbours' rows (``view``: relative offsets, distances and last broadcasts, nearest first),
its own sensors (``sense``: tick, floor sensor, odometry, beacon bearing), its floor probe
(``probe``) and the run's parameters (``P``). Nothing else: no positions, no other robot's
state. decide.py calls them, one robot at a time, for a chunk of robots.

Modules, by rule family: common (geometry, actions, views), gradient (Algorithm 1 and the
movers' gradient), travel (Initial: formation move, the leader to the beacon), detection
(Algorithm 7), coverage (Algorithm 2: edge following, wandering, boundary fill, giving way),
arrival (Algorithm 2's stop rules), intergroup (Section 4.3: the rule sets), deadlock
(Equation 3, Algorithms 5-6), surplus (the surplus lap), aggregation (Algorithms 3-4 and
Figure 7: the scattered start).
"""

"""Flow: movers walk through the structure and settle at the first free lattice site.

With the rule set's THROUGH flag (our addition; rule set "flow"). Arrived robots stand d_cover
(6) apart and a body's radius is 0.4, so the structure leaves ~5 units between bodies: a mover
can walk through it instead of round its perimeter, single file, to its far edge. Movers then
reach the frontier by many ways at once, and no longer walk the whole edge to its end.

* **A free site.** Two arrived robots (any group) a pair apart (d_cover - PAIR_SHORT to
  d_cover + PAIR_LONG) make a site on each side: the point d_cover from both (triangle
  completion, so the lattice stays hexagonal and covers). A site within SITE_REACH of me is
  free when no stationary robot I hear is nearer to it than d_cover - arrive_tolerance, no
  mover nearer to it than I am is within SITE_TAKEN of it, and I have not found it off the
  target.
* **Settling.** On the target, I go to the nearest free site, passing placed bodies
  (:func:`steer`), while the probe finds target floor at it (or, farther than the probe
  reaches, HOLE_PROBE on my way to it). Off the target, I remember it (schema.BAN_SLOTS
  sites, carried by my odometry) and look no more this tick. Within SITE_REACHED of it I
  arrive, with 1 + the lowest gradient of my group's arrived robots near (:func:`settle_gradient`). At most two probes a tick (the
  site's and the climb's), so that today's rules keep theirs (rules/common.MAX_PROBES).
* **Climbing.** With no free site in reach, off the target I step into the structure beside
  me (toward its arrived robots' centroid: they stand on the target); on it I climb the
  arrived robots' gradient (it grows away from where their group entered), of the group of
  my nearest arrived robot: from the centroid of that group's lowest-gradient arrived
  robots within CLIMB_REACH toward the centroid of the highest, drawn
  inward by the arrived robots' centroid (:func:`way_on`), passing bodies, while the probe
  finds target floor that way (HOLE_PROBE ahead). The frontier lies that way, and its free sites.
* **Not beside formations.** Within d_cover of a waiting robot (Initial, Detection) I follow
  today's rules: a formation is packed too close to walk through, and a mover pressed
  against it holds its release back (Algorithm 7).
* **Falling back.** No site and no way up (flat gradient, no arrived robot near,
  target floor ends ahead), or stuck (Equation 3): I follow the edge by today's rules
  (coverage.py) for REST_PATH units before I look again.
"""

from __future__ import annotations

import math

from numba import njit

from ..schema import BAN_SLOTS
from ..statuses import ARRIVE
from .common import INF, is_waiting, probe, scaled, within
from .holes import HOLE_PROBE
from .rulesets import THROUGH

BAN_RADIUS = 1.0
"""A site within this distance (units) of one remembered is that site."""
PAIR_SHORT = 0.5
"""Two arrived robots at least d_cover - this apart (units) make sites."""
PAIR_LONG = 1.0
"""... and at most d_cover + this (d_cover + 1 <= lattice_reach at d_cover 6: the pair's
gap stays covered)."""
SITE_REACH = 6.0
"""A mover goes for free sites within this distance (units)."""
SITE_TAKEN = 2.0
"""A mover this close to a site (units), and nearer to it than I am, is taking it."""
SITE_REACHED = 0.3
"""A mover this close to its site (units) arrives (on the target)."""
CLIMB_REACH = 9.0
"""A mover climbs the gradient of its group's arrived robots within this distance (units)."""
INWARD_PULL = 1.0
"""How hard the arrived robots' centroid draws a climbing mover inward (see :func:`way_on`)."""
AVOID = 1.5
"""A mover passes a body within this distance (units) round its side."""
REST_PATH = 40.0
"""Units a mover follows the edge by today's rules after the flow found it no way."""
NO_FLOW, FLOW_DRIVE, FLOW_ARRIVE = 0, 1, 2
"""What :func:`flow` decided: nothing (today's rules apply), drive, arrive here."""


@njit(cache=True)
def waiting_within(view, reach):  # pragma: no cover - compiled
    """Is a waiting robot (Initial, Detection; any group) within ``reach``?"""
    for r in range(within(view.dist, reach)):
        if is_waiting(view.status[r]):
            return True
    return False


@njit(cache=True)
def carry_bans(me, sense):  # pragma: no cover - compiled
    """Keep my remembered sites relative to me: move them by this tick's displacement."""
    for s in range(BAN_SLOTS):
        me.ban_x[s] -= sense.moved_x
        me.ban_y[s] -= sense.moved_y


@njit(cache=True)
def banned(me, px, py):  # pragma: no cover - compiled
    for s in range(min(me.ban_next, BAN_SLOTS)):
        if math.hypot(me.ban_x[s] - px, me.ban_y[s] - py) <= BAN_RADIUS:
            return True
    return False


@njit(cache=True)
def ban(me, px, py):  # pragma: no cover - compiled
    s = me.ban_next % BAN_SLOTS
    me.ban_x[s], me.ban_y[s] = px, py
    me.ban_next += 1


@njit(cache=True)
def site_free(view, px, py, d, P):  # pragma: no cover - compiled
    """No stationary robot within d_cover - arrive_tolerance of (px, py), ``d`` (units)
    away from me, and no mover within SITE_TAKEN of it nearer than I am (movers passing by
    do not hold a site: a stream of them would hide every site beside its way)."""
    clear = P.d_cover - P.arrive_tolerance
    for r in range(len(view.dist)):
        gap = math.hypot(view.off[r, 0] - px, view.off[r, 1] - py)
        if view.moving[r]:
            if gap < min(SITE_TAKEN, d):
                return False
        elif gap < clear:
            return False
    return True


@njit(cache=True)
def nearest_site(view, me, P):  # pragma: no cover - compiled
    """The nearest free site within SITE_REACH (see the module docstring): (found, x, y)."""
    k = within(view.dist, SITE_REACH + P.d_cover)
    best, bx, by = math.inf, 0.0, 0.0
    for a in range(k):
        if view.status[a] != ARRIVE or view.moving[a]:
            continue
        for b in range(a + 1, k):
            if view.status[b] != ARRIVE or view.moving[b]:
                continue
            dx, dy = view.off[b, 0] - view.off[a, 0], view.off[b, 1] - view.off[a, 1]
            base = math.hypot(dx, dy)
            if base < P.d_cover - PAIR_SHORT or base > P.d_cover + PAIR_LONG:
                continue
            height = math.sqrt(max(P.d_cover * P.d_cover - 0.25 * base * base, 0.0))
            mx, my = 0.5 * (view.off[a, 0] + view.off[b, 0]), 0.5 * (view.off[a, 1] + view.off[b, 1])
            nx, ny = -dy / base * height, dx / base * height
            for side in (-1.0, 1.0):
                px, py = mx + side * nx, my + side * ny
                d = math.hypot(px, py)
                if d >= best or d > SITE_REACH or banned(me, px, py):
                    continue
                if site_free(view, px, py, d, P):
                    best, bx, by = d, px, py
    return best < math.inf, bx, by


@njit(cache=True)
def settle_gradient(view, me, P):  # pragma: no cover - compiled
    """Settling: my gradient is 1 + the lowest of my group's arrived robots within 1.5 d_cover
    (none: I keep mine), so that each group's gradient keeps counting hops from its entry."""
    low = INF
    for r in range(within(view.dist, 1.5 * P.d_cover)):
        if view.status[r] == ARRIVE and view.group[r] == me.group:
            low = min(low, view.gradient[r])
    if low < INF:
        me.gradient = low + 1


@njit(cache=True)
def climb_direction(view):  # pragma: no cover - compiled
    """Unit direction from the lowest-gradient arrived robots within CLIMB_REACH toward the
    highest ones, of the group of my nearest arrived robot (gradients are per group; where
    my group's structure ends inside another's, that group's gradient leads on); (0, 0):
    none (fewer than two gradients)."""
    k = within(view.dist, CLIMB_REACH)
    group = -1
    for r in range(k):
        if view.status[r] == ARRIVE:
            group = view.group[r]
            break
    if group < 0:
        return 0.0, 0.0
    low, high = INF, -1
    for r in range(k):
        if view.status[r] == ARRIVE and view.group[r] == group and view.gradient[r] < INF:
            low = min(low, view.gradient[r])
            high = max(high, view.gradient[r])
    if high <= low:
        return 0.0, 0.0
    lx, ly, ln, hx, hy, hn = 0.0, 0.0, 0, 0.0, 0.0, 0
    for r in range(k):
        if view.status[r] != ARRIVE or view.group[r] != group:
            continue
        if view.gradient[r] == low:
            lx, ly, ln = lx + view.off[r, 0], ly + view.off[r, 1], ln + 1
        elif view.gradient[r] == high:
            hx, hy, hn = hx + view.off[r, 0], hy + view.off[r, 1], hn + 1
    return scaled(hx / hn - lx / ln, hy / hn - ly / ln, 1.0)


@njit(cache=True)
def arrived_centroid(view):  # pragma: no cover - compiled
    """The mean offset (units) of the arrived robots (any group) within CLIMB_REACH; (0, 0):
    none."""
    x, y, n = 0.0, 0.0, 0
    for r in range(within(view.dist, CLIMB_REACH)):
        if view.status[r] == ARRIVE:
            x, y, n = x + view.off[r, 0], y + view.off[r, 1], n + 1
    return (x / n, y / n) if n else (0.0, 0.0)


@njit(cache=True)
def way_on(view, me, sense):  # pragma: no cover - compiled
    """My way on (unit; (0, 0): none): off the target, into the structure beside me (toward
    its arrived robots' centroid); on it, up the nearest arrived robot's group's gradient, drawn inward by that
    centroid (INWARD_PULL at CLIMB_REACH / 2 from it), so that a mover on the structure's
    rim walks in, not along it."""
    ix, iy = arrived_centroid(view)
    if not sense.on_target:
        return scaled(ix, iy, 1.0)
    cx, cy = climb_direction(view)
    pull = INWARD_PULL / (0.5 * CLIMB_REACH)
    return scaled(cx + ix * pull, cy + iy * pull, 1.0)


@njit(cache=True)
def steer(view, ux, uy, P):  # pragma: no cover - compiled
    """Heading (ux, uy) (unit), turned to pass each stationary body within AVOID ahead on its
    side away from my heading (a unit vector)."""
    sx, sy = ux, uy
    for r in range(within(view.dist, AVOID)):
        if view.moving[r]:
            continue
        ox, oy = view.off[r, 0], view.off[r, 1]
        d = max(view.dist[r], 1e-9)
        if ox * ux + oy * uy <= 0:
            continue
        side = ox * -uy + oy * ux  # > 0: the body is on my left
        s = -1.0 if side > 0 else 1.0
        push = (AVOID - d) / AVOID
        sx += s * -uy * (1.0 + push) - ox / d * push
        sy += s * ux * (1.0 + push) - oy / d * push
    return scaled(sx, sy, 1.0)


@njit(cache=True)
def flow(view, me, sense, pb, stuck_now, P):  # pragma: no cover - compiled
    """This tick of the flow (see the module docstring): (NO_FLOW | FLOW_DRIVE | FLOW_ARRIVE,
    vx, vy)."""
    if not (P.flags & THROUGH):
        return NO_FLOW, 0.0, 0.0
    carry_bans(me, sense)
    if stuck_now:
        me.flow_rest = me.path + REST_PATH
    if me.path < me.flow_rest or waiting_within(view, P.d_cover):
        return NO_FLOW, 0.0, 0.0
    if sense.on_target:
        found, px, py = nearest_site(view, me, P)
        if found:
            d = math.hypot(px, py)
            if d <= SITE_REACHED:
                settle_gradient(view, me, P)
                return FLOW_ARRIVE, 0.0, 0.0
            reach = min(HOLE_PROBE, d) / d  # the site, or the floor on my way to it
            if probe(pb, px * reach, py * reach):
                ux, uy = steer(view, px / d, py / d, P)
                speed = min(P.v, d)
                return FLOW_DRIVE, ux * speed, uy * speed
            ban(me, px, py)
    ux, uy = way_on(view, me, sense)
    if (ux == 0.0 and uy == 0.0) or (sense.on_target
                                     and not probe(pb, ux * HOLE_PROBE, uy * HOLE_PROBE)):
        me.flow_rest = me.path + REST_PATH
        return NO_FLOW, 0.0, 0.0
    ux, uy = steer(view, ux, uy, P)
    return FLOW_DRIVE, ux * P.v, uy * P.v

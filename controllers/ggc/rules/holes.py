"""Holes: arrived robots point movers at uncovered spots inside the structure (our addition).

Robots that arrive a little too far apart leave spots inside the structure that no robot
covers. Movers follow the structure's outer edge and never reach them, so runs end on a
plateau short of completion (docs/reports/ggc-findings-journal.md, "Holes sealed inside the
structure").
Applies while d_cover + arrive_tolerance <= lattice_reach (swarm.rule_flags): a wider lattice
leaves holes by design.

* **Finding a hole.** An arrived robot inside the structure (its arrived neighbours within
  hole reach, d_cover + r, leave no angular gap of HOLE_GAP or more) looks at each triangle it
  makes with two angularly consecutive arrived neighbours. A triangle whose circumcentre lies
  inside it, farther than r + HOLE_MARGIN from every stationary robot heard (r: the coverage
  radius, lattice_reach / sqrt(3)), has a hole there, if the floor probe finds target floor
  on the way to it (a triangle across a concave corner of the target has its centre off the
  target). The robot reports the hole once it has seen it for HOLE_AGE ticks (the growing
  edge of the structure is not a hole).
* **Holes too large for a triangle.** A robot on the structure's edge (a gap of HOLE_GAP or
  more) on the target reports the spot d_cover out along the middle of its widest gap, if
  the probe finds target floor that way and it has seen no mover for HOLE_AGE ticks: a large
  hole sealed in when the structure closed round it (the large K above its junction, the
  small K's upper arm with eight groups). An edge that movers reach is theirs.
* **Passing it on.** Such a robot broadcasts hops 0 and the hole's offset from itself; an
  arrived robot that finds none takes 1 + the fewest hops an arrived neighbour broadcasts,
  with that neighbour's hole seen from itself, up to HOLE_HOPS hops, and only while it cannot
  see the hole covered. Arrived robots look again every HOLE_PERIOD ticks.
* **Filling it.** A mover that has walked HOLE_PATH units since it left its formation, hears
  a hole that no stationary robot it sees covers, and sees no mover nearer to it, goes
  straight for it through the structure, sidestepping robots in its way, and arrives there
  (or, on the target, where its floor probe finds the hole off the target). A mover stuck on
  its way, or off the target and finding the hole off it too, rests from holes HOLE_REST
  ticks.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..schema import NO_HOLE
from ..statuses import ARRIVE
from .common import probe, rest, scaled, set_status, within

HOLE_HOPS = 12
"""How far (hops through arrived robots) news of a hole travels."""
HOLE_PERIOD = 50
"""Ticks between an arrived robot's looks for holes."""
HOLE_MARGIN = 0.5
"""Only a triangle whose circumradius is more than r + HOLE_MARGIN (units) has a hole worth a
robot (a slightly wide triangle leaves a sliver uncovered, and filling it costs a whole
robot)."""
HOLE_GAP = math.radians(150)
"""An arrived robot whose arrived neighbours leave an angular gap this wide is on the
structure's edge: it reports no triangle's hole, only the open floor beyond it, and only
while no mover comes by (:func:`open_beyond`)."""
HOLE_AGE = 1000
"""Ticks an arrived robot must have seen the same hole before it reports it: while the
structure grows, movers following its edge fill its gaps; a hole still open this long is
sealed in."""
HOLE_SAME = 1.0
"""A hole seen again within this distance (units) of where it was is the same hole."""
HOLE_PATH = 250.0
"""A mover goes for holes only once it has walked this far (units) since it left its
formation without finding a place: while the structure grows, movers are better spent on
its edge."""
HOLE_REST = 500
"""Ticks a mover that got stuck on its way to a hole ignores holes."""
HOLE_REACHED = 0.5
"""A mover this close to its hole (units) arrives."""
HOLE_PROBE = 1.9
"""How far the floor probe looks toward a hole (units, within the engine's probe range): a
mover probes its hole from this close, an arrived robot the floor this far toward it."""


@njit(cache=True)
def cover_radius(P):  # pragma: no cover - compiled
    """r, the coverage radius: lattice_reach is r * sqrt(3)."""
    return P.lattice_reach / math.sqrt(3.0)


@njit(cache=True)
def covered(view, px, py, r):  # pragma: no cover - compiled
    """Is (px, py) (relative to me) within r of a stationary robot I hear?"""
    for k in range(len(view.dist)):
        if not view.moving[k] and math.hypot(view.off[k, 0] - px, view.off[k, 1] - py) <= r:
            return True
    return False


@njit(cache=True)
def circumcentre(bx, by, cx, cy):  # pragma: no cover - compiled
    """Circumcentre of the triangle (0, B, C); (False, 0, 0) if degenerate."""
    d = 2.0 * (bx * cy - by * cx)
    if abs(d) < 1e-9:
        return False, 0.0, 0.0
    b2, c2 = bx * bx + by * by, cx * cx + cy * cy
    return True, (cy * b2 - by * c2) / d, (bx * c2 - cx * b2) / d


@njit(cache=True)
def inside(px, py, bx, by, cx, cy):  # pragma: no cover - compiled
    """Is P inside the triangle (0, B, C)?"""
    d1 = -px * by + py * bx
    d2 = (bx - px) * (cy - by) - (by - py) * (cx - bx)
    d3 = (cx - px) * (-cy) - (cy - py) * (-cx)
    neg = d1 < 0 or d2 < 0 or d3 < 0
    pos = d1 > 0 or d2 > 0 or d3 > 0
    return not (neg and pos)


@njit(cache=True)
def find_hole(view, sense, pb, P):  # pragma: no cover - compiled
    """The widest hole beside me (see the module docstring): (found, x, y) relative to me."""
    r = cover_radius(P)
    k = within(view.dist, P.d_cover + r)
    rows = np.empty(max(k, 1), dtype=np.int64)
    angles = np.empty(max(k, 1))
    n = 0
    for j in range(k):
        if view.status[j] == ARRIVE and not view.moving[j]:
            rows[n] = j
            angles[n] = math.atan2(view.off[j, 1], view.off[j, 0])
            n += 1
    if n < 3:
        return False, 0.0, 0.0
    order = np.argsort(angles[:n])
    widest, best, hx, hy = 0.0, r + HOLE_MARGIN, 0.0, 0.0
    middle = 0.0  # the bearing of the middle of my widest gap
    for i in range(n):
        a, b = order[i], order[(i + 1) % n]
        gap = (angles[b] - angles[a]) % (2 * math.pi)
        if gap > widest:
            middle = angles[a] + 0.5 * gap
        widest = max(widest, gap if n > 1 else 2 * math.pi)
        bx, by = view.off[rows[a], 0], view.off[rows[a], 1]
        cx, cy = view.off[rows[b], 0], view.off[rows[b], 1]
        ok, ox, oy = circumcentre(bx, by, cx, cy)
        if not ok or not inside(ox, oy, bx, by, cx, cy):
            continue
        radius = math.hypot(ox, oy)
        if radius > best and not covered(view, ox, oy, r):
            best, hx, hy = radius, ox, oy
    if widest >= HOLE_GAP and sense.on_target:
        return open_beyond(view, pb, math.cos(middle), math.sin(middle), P)
    if widest >= HOLE_GAP or best <= r + HOLE_MARGIN or not sense.on_target:
        return False, 0.0, 0.0
    reach = min(HOLE_PROBE, best) / best  # the floor on my way to it: a triangle across a
    if not probe(pb, hx * reach, hy * reach):  # concave corner has its centre off the target
        return False, 0.0, 0.0
    return True, hx, hy


@njit(cache=True)
def open_beyond(view, pb, x, y, P):  # pragma: no cover - compiled
    """On the structure's edge (a gap of HOLE_GAP or more, (x, y) the unit vector to its
    middle): the open floor d_cover out that way, as a hole (found, x, y), while no mover is
    in sight and the floor probe finds target toward it. An edge that movers come by is
    theirs; one they have not come by for HOLE_AGE ticks (settled) rims a hole sealed off
    from them."""
    for j in range(len(view.dist)):
        if view.moving[j]:
            return False, 0.0, 0.0
    if not probe(pb, x * HOLE_PROBE, y * HOLE_PROBE):
        return False, 0.0, 0.0  # the target's boundary
    return True, x * P.d_cover, y * P.d_cover


@njit(cache=True)
def relay(view, P):  # pragma: no cover - compiled
    """1 + the fewest hops an arrived neighbour broadcasts (within hole reach), and that hole
    seen from me; NO_HOLE if none is heard within HOLE_HOPS or I see it covered."""
    r = cover_radius(P)
    hops, hx, hy = NO_HOLE, 0.0, 0.0
    for j in range(within(view.dist, P.d_cover + r)):
        h = int(view.hole[j]) + 1
        if view.status[j] != ARRIVE or view.moving[j] or h >= hops or h > HOLE_HOPS:
            continue
        px, py = view.off[j, 0] + view.hole_x[j], view.off[j, 1] + view.hole_y[j]
        if covered(view, px, py, r):
            continue
        hops, hx, hy = h, px, py
    return hops, hx, hy


@njit(cache=True)
def settled(view, me, sense, pb, P):  # pragma: no cover - compiled
    """An arrived robot's tick: with hole filling, look for holes and pass news of them on,
    then sleep until the next look."""
    found, hx, hy = find_hole(view, sense, pb, P)
    if not found:
        me.seen_since = -1
    elif me.seen_since < 0 or math.hypot(hx - me.seen_x, hy - me.seen_y) > HOLE_SAME:
        me.seen_since = sense.tick
    me.seen_x, me.seen_y = hx, hy
    if found and sense.tick - me.seen_since >= HOLE_AGE:
        me.hole, me.hole_x, me.hole_y = 0, hx, hy
    else:
        me.hole, me.hole_x, me.hole_y = relay(view, P)
    return rest(0.0, True, sense.tick + HOLE_PERIOD)


@njit(cache=True)
def nearer_mover(view, px, py, d):  # pragma: no cover - compiled
    """Is a mover I see nearer than ``d`` to (px, py) (relative to me)?"""
    for k in range(len(view.dist)):
        if view.moving[k] and math.hypot(view.off[k, 0] - px, view.off[k, 1] - py) < d:
            return True
    return False


@njit(cache=True)
def hole_heard(view, me, sense, P):  # pragma: no cover - compiled
    """The nearest-by-hops hole that arrived robots I hear report, that no stationary robot
    I see covers (within 0.75 r) and that no mover I see is nearer to: (found, x, y)
    relative to me. None while I rest from holes."""
    if sense.tick < me.hole_rest or me.path < HOLE_PATH:
        return False, 0.0, 0.0
    r = cover_radius(P)
    hops, best, hx, hy = NO_HOLE, math.inf, 0.0, 0.0
    for j in range(len(view.dist)):
        h = int(view.hole[j])
        if view.status[j] != ARRIVE or view.moving[j] or h > hops or h >= NO_HOLE:
            continue
        px, py = view.off[j, 0] + view.hole_x[j], view.off[j, 1] + view.hole_y[j]
        d = math.hypot(px, py)
        if (h == hops and d >= best) or covered(view, px, py, 0.75 * r):
            continue
        if nearer_mover(view, px, py, d):
            continue
        hops, best, hx, hy = h, d, px, py
    return hops < NO_HOLE, hx, hy


@njit(cache=True)
def sidestep(view, hx, hy, d, P):  # pragma: no cover - compiled
    """Heading (hx, hy) (unit), turned to pass the nearest robot within 2 d_safe ahead (and
    nearer than ``d``, units) on the side away from it."""
    for j in range(within(view.dist, 2.0 * P.d_safe)):
        if view.dist[j] >= d:
            break
        ahead = view.off[j, 0] * hx + view.off[j, 1] * hy
        if ahead > 0:
            side = view.off[j, 0] * -hy + view.off[j, 1] * hx
            s = -1.0 if side > 0 else 1.0
            return scaled(hx - s * hy, hy + s * hx, 1.0)
    return hx, hy


@njit(cache=True)
def to_hole(view, me, sense, pb, hx, hy, P):  # pragma: no cover - compiled
    """Head for the hole at (hx, hy), sidestepping a robot close ahead; arrive on it (or,
    on the target, where the probe finds it off the target). (arrived, vx, vy)."""
    d = math.hypot(hx, hy)
    off_target = d <= HOLE_PROBE and not probe(pb, hx, hy)
    if sense.on_target and (d <= HOLE_REACHED or off_target):
        set_status(me, ARRIVE)
        return True, 0.0, 0.0
    if off_target:  # news of a hole off the target: not mine to fill
        me.hole_rest = sense.tick + HOLE_REST
        return False, 0.0, 0.0
    ux, uy = sidestep(view, hx / max(d, 1e-9), hy / max(d, 1e-9), d, P)
    me.head_x, me.head_y = ux, uy
    speed = min(P.v, d)
    return False, ux * speed, uy * speed

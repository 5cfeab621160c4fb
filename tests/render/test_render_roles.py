"""What frames show of groups and leaders: at tick 0, without the fields, in the legend."""

from __future__ import annotations

import numpy as np
import pygame
import pytest

from swarmsim.engine.sim import Simulation
from swarmsim.render import Renderer
from swarmsim.render.legend import _swatch
from swarmsim.render.palette import GROUP_PALETTE, LEADER_RING, NONE_GREY
from swarmsim.results.snapshot import Snapshot


def renderer(sim: Simulation, **kw) -> Renderer:
    """A renderer with the run's controller's colourings, leader and group fields."""
    return Renderer(sim.world, colourings=sim.info.colourings, group_field=sim.info.group_field,
                    leader_field=sim.info.leader_field, **kw)


@pytest.fixture(scope="module")
def tick0() -> tuple[Simulation, Snapshot]:
    sim = Simulation("tiny", controller="ggc", robots=40, groups=3, seed=0, max_ticks=10,
                     settings={"start": "formation"})
    return sim, sim.snapshot()


def test_tick_zero_counts_the_formations_that_stand(tick0) -> None:
    sim, snap = tick0
    assert (snap.messages["status"] < 0).all()  # nobody has broadcast yet
    text = renderer(sim).hud_text(snap)
    assert text.endswith("groups 3"), text


def test_tick_zero_colours_robots_by_their_start_group_and_rings_leaders(tick0) -> None:
    sim, snap = tick0
    r = renderer(sim, color_by="group", hud=False, legend=False)
    colours = r.robot_colors(snap)
    expected = GROUP_PALETTE[(snap.start_groups - 1) % len(GROUP_PALETTE)]
    assert (snap.start_groups > 0).all()
    np.testing.assert_array_equal(colours, expected)
    assert not (colours == np.uint8(NONE_GREY)).all(axis=1).any()
    # the three leaders' rings: black pixels at each leader's ring radius
    frame = r.draw(snap)
    pix = np.rint(r.world_to_pixel(snap.positions[snap.start_leaders])).astype(int)
    assert len(pix) == 3
    for x, y in pix:
        patch = frame[y - 8:y + 9, x - 8:x + 9]
        assert (patch == np.uint8(LEADER_RING)).all(axis=2).sum() >= 4


def _without(snap: Snapshot, drop: set[str]) -> Snapshot:
    names = [n for n in snap.messages.dtype.names if n not in drop]
    msgs = np.zeros(snap.n_robots, dtype=[(n, snap.messages.dtype[n]) for n in names])
    for n in names:
        msgs[n] = snap.messages[n]
    return Snapshot(snap.tick, snap.positions, msgs, snap.statuses, snap.radius, snap.coverage,
                    snap.covered, snap.in_contact, snap.failed, snap.start_groups,
                    snap.start_leaders)


def test_broadcasts_without_group_gradient_or_leader_still_draw(tick0) -> None:
    sim, snap = tick0
    bare = _without(snap, {"group", "gradient", "leader"})
    for colour in ("gradient", "group", "status"):
        r = renderer(sim, color_by=colour)
        frame = r.draw(bare)
        assert frame.shape == r.shape
        assert "groups" not in r.hud_text(bare)
    grey = renderer(sim, color_by="group").robot_colors(bare)
    assert (grey == np.uint8(NONE_GREY)).all()


def test_the_legend_leader_is_a_coloured_disc_with_a_black_ring() -> None:
    pygame.font.init()
    font = pygame.font.Font(None, 24)
    fill = tuple(GROUP_PALETTE[0].tolist())
    s = _swatch(font, "ringed", LEADER_RING, "leader", fill)
    size = max(6, font.get_linesize() - 4)
    cx, cy = size // 2, s.get_height() // 2
    assert tuple(s.get_at((cx, cy)))[:3] == fill  # filled, not an open circle
    edge = [tuple(s.get_at((cx + dx, cy)))[:3] for dx in range(size // 2 + 1)]
    assert LEADER_RING in edge

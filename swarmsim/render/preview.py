"""A world's preview without running it: the arena, target, holes, obstacles, spawn areas and
beacon, the robots where the world's default start puts them (seed 0), target floor too narrow
for a robot in red, and a caption with the free area and lattice capacity
(``swarmsim worlds PATH --preview FILE.png``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pygame
import shapely

from swarmsim.errors import ConfigError
from swarmsim.render.frame import Renderer
from swarmsim.render.palette import OUTSIDE, PANEL, TEXT
from swarmsim.render.video import save_png
from swarmsim.results.snapshot import Snapshot
from swarmsim.world.worldinfo import (
    DEFAULT_D_COVER,
    DEFAULT_ROBOTS,
    ROBOT_RADIUS,
    START_SPACING,
    WorldReport,
    free_floor,
    layout_rng,
    narrow_floor,
)

NARROW = (230, 40, 40)
WARN = (170, 20, 20)


def start_layout(report: WorldReport, seed: int = 0) -> tuple[np.ndarray, np.ndarray,
                                                              np.ndarray, str]:
    """Positions (n, 2), groups (n,) and leader flags (n,) of the world's default start, and a
    note ("" or why no robots are drawn). The default start is the world's ``start``, else a
    formation (GGC's), with its ``robots`` (else 100) in its ``groups`` (else 1)."""
    from swarmsim.world import spawn

    w = report.world
    robots = int(w.defaults.get("robots", DEFAULT_ROBOTS))
    groups = int(w.defaults.get("groups", 1))
    rng = layout_rng(seed)
    try:
        if w.defaults.get("start", "formation") == "formation":
            pos, grp, lead = spawn.formation_layout(w, robots, groups, START_SPACING, rng)
            leaders = np.zeros(robots, dtype=bool)
            leaders[lead] = True
            return pos, grp.astype(np.int64), leaders, ""
        pos = spawn.random_layout(w, robots, START_SPACING, rng, clearance=ROBOT_RADIUS)
        return pos, np.zeros(robots, dtype=np.int64), np.zeros(robots, dtype=bool), ""
    except ConfigError:
        empty = np.zeros((0, 2))
        return (empty, np.zeros(0, np.int64), np.zeros(0, bool),
                f"the default start of {robots} robots does not fit (see warnings)")


def draw_preview(report: WorldReport, width: int = 800) -> np.ndarray:
    """The preview as an (H, W, 3) uint8 RGB array."""
    w = report.world
    pos, grp, lead, note = start_layout(report)
    n = len(pos)
    msgs = np.zeros(n, dtype=[("status", "i1"), ("group", "i2"), ("leader", "?")])
    msgs["status"] = -1  # nothing broadcast: the renderer shows the start roles
    snap = Snapshot(tick=0, positions=pos, messages=msgs, statuses=("start",),
                    radius=ROBOT_RADIUS, coverage=0.0, covered=None,
                    in_contact=np.zeros(n, bool), failed=np.zeros(n, bool),
                    start_groups=grp, start_leaders=lead)
    renderer = Renderer(w, width=width, color_by="group", hud=False,
                        colourings={"group": "category"}, group_field="group",
                        leader_field="leader")  # the fields of the snapshot made above
    frame = renderer.draw_surface(snap)
    _draw_narrow(frame, renderer, report)
    caption = _caption_panel(renderer.width, report, note)
    extra = caption.get_height() if caption is not None else 0
    extra += extra % 2  # even sides, like every frame
    surf = pygame.Surface((renderer.width, renderer.height + extra))
    surf.fill(OUTSIDE)
    surf.blit(frame, (0, 0))
    if caption is not None:  # below the world, so that it hides nothing
        surf.blit(caption, (0, renderer.height))
    data = pygame.image.tobytes(surf, "RGB")
    return np.frombuffer(data, dtype=np.uint8).reshape(surf.get_height(), surf.get_width(), 3)


def save_preview(report: WorldReport, path: str | Path, width: int = 800) -> Path:
    """Draw the preview and write it as a PNG (atomically); returns the path."""
    path = Path(path)
    save_png(draw_preview(report, width), path)
    return path


def _draw_narrow(surf: pygame.Surface, renderer: Renderer, report: WorldReport) -> None:
    """Free target floor narrower than a robot, filled red."""
    if report.narrow_area <= 0:
        return
    narrow = narrow_floor(free_floor(report.world))
    for part in shapely.get_parts(narrow):
        if part.geom_type != "Polygon" or part.is_empty:
            continue
        ring = renderer.world_to_pixel(np.asarray(part.exterior.coords)[:, :2]).tolist()
        if len(ring) >= 3:
            pygame.draw.polygon(surf, NARROW, ring)


def _caption(report: WorldReport, note: str) -> list[tuple[str, tuple[int, int, int]]]:
    w = report.world
    d = float(w.defaults.get("d_cover", DEFAULT_D_COVER))
    robots = int(w.defaults.get("robots", DEFAULT_ROBOTS))
    lines = [((f"{w.name}: free target floor {report.free_area:,.0f} units^2, lattice holds "
              f"{report.capacity[d]:,} at d_cover {d:g}"), TEXT),
             ((f"{robots} robots, {int(w.defaults.get('groups', 1))} group(s); spawn holds "
              f"~{report.spawn_capacity:,}"), TEXT)]
    if report.narrow_area > 0:
        lines.append((f"red: {report.narrow_area:,.1f} units^2 of target narrower than a robot",
                      NARROW))
    if note:
        lines.append((note, WARN))
    if report.warnings:
        lines.append(((f"{len(report.warnings)} warning(s): see 'swarmsim worlds "
                      f"{w.source}'"), WARN))
    return lines


def _caption_panel(width: int, report: WorldReport, note: str) -> pygame.Surface | None:
    """The caption's lines on a white panel ``width`` pixels wide, or None without fonts."""
    try:
        pygame.font.init()
        font = pygame.font.Font(None, max(12, round(width / 38)))
    except (ImportError, NotImplementedError, OSError, RuntimeError, pygame.error):
        return None  # no fonts: the picture without its caption
    texts = [font.render(t, True, c) for t, c in _caption(report, note)]
    margin = max(3, width // 160)
    inner = width - 2 * margin
    texts = [pygame.transform.smoothscale_by(t, inner / t.get_width())
             if t.get_width() > inner else t for t in texts]
    panel = pygame.Surface((width, sum(t.get_height() for t in texts) + margin))
    panel.fill(PANEL[:3])
    y = margin // 2
    for t in texts:
        panel.blit(t, (margin, y))
        y += t.get_height()
    return panel

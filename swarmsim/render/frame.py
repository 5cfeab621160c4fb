"""Headless frame rendering: a :class:`~swarmsim.results.snapshot.Snapshot` -> an (H, W, 3) uint8 image.

Everything is drawn with pygame-ce on an off-screen ``Surface``: no window, no audio, no
``pygame.init()``. The static part of the picture (arena walls, target with its holes, obstacles,
spawn outlines, beacon) is drawn once into a cached background; each frame copies it, then draws
the coverage tint, the robots, a heads-up line and a legend.

World coordinates have y growing upward; image rows grow downward, so the camera flips y.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from typing import Any

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")
os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")

import numpy as np
import pygame
import pygame.font
import shapely

from swarmsim.limits import MAX_FRAME_SIDE
from swarmsim.metrics import CoverageGrid
from swarmsim.render import roles
from swarmsim.render.legend import legend_panel
from swarmsim.render.palette import (
    BEACON_EDGE,
    BEACON_FILL,
    COLORKEY,
    CONTACT_RING,
    COVER_FILL,
    FAILED,
    FAILED_MARK,
    FLOOR,
    GRADIENT_PALETTE,
    GROUP_PALETTE,
    HEADING_MARK,
    LEADER_RING,
    NONE_GREY,
    OBSTACLE_EDGE,
    OBSTACLE_FILL,
    OUTSIDE,
    PANEL,
    SPAWN_EDGE,
    STATUS_PALETTE,
    TARGET_EDGE,
    TARGET_FILL,
    TEXT,
    WALL,
)
from swarmsim.results.snapshot import Snapshot
from swarmsim.world.world import World

MIN_WIDTH = 64


DEFAULT_WIDTH = 800
"""px, a frame's width unless asked otherwise."""


def check_width(width: Any) -> None:
    """Raise ValueError unless ``width`` (pixels) is an even integer in [MIN_WIDTH,
    MAX_FRAME_SIDE] (H.264 needs even frame sides)."""
    if (isinstance(width, bool) or not isinstance(width, (int, np.integer))
            or not MIN_WIDTH <= width <= MAX_FRAME_SIDE or width % 2):
        raise ValueError(f"width must be an even integer >= {MIN_WIDTH} and at most "
                         f"{MAX_FRAME_SIDE:,}, got {width!r}")


def frame_size(arena: tuple[float, float, float, float], width: int) -> tuple[int, int]:
    """(width, height) in pixels of frames of ``arena`` (xmin, ymin, xmax, ymax) ``width``
    pixels wide: the height follows the arena's aspect ratio, rounded to a multiple of 16
    when ``width`` is one, else to an even number. ValueError if the width is refused
    (check_width), the arena has no area, or the height exceeds MAX_FRAME_SIDE."""
    check_width(width)
    xmin, ymin, xmax, ymax = (float(v) for v in arena)
    ww, wh = xmax - xmin, ymax - ymin
    if not (ww > 0 and wh > 0):
        raise ValueError(f"world arena has no area: {arena!r}")
    width = int(width)
    height = _even(width * wh / ww, 16 if width % 16 == 0 else 2)
    if height > MAX_FRAME_SIDE:
        most = int(MAX_FRAME_SIDE * ww / wh) // 2 * 2
        raise ValueError(f"width {width} makes frames {height:,} px high for this arena "
                         f"({ww:g} x {wh:g} units), more than {MAX_FRAME_SIDE:,}: give a width "
                         f"of at most {most}")
    return width, height


def _even(x: float, multiple: int) -> int:
    return max(multiple, round(x / multiple) * multiple)


HEADING_MIN_PX = 3
"""Robots drawn smaller than this radius (pixels) get no heading mark."""


def _draw_heading_marks(surf: pygame.Surface, centres: np.ndarray, headings: np.ndarray,
                        ri: int) -> None:
    """A line from each robot's centre (pixels, (K, 2) int) toward its heading (radians,
    world frame, (K,)), 0.8 of the drawn radius ``ri`` long; the image's y axis points down.
    Robots with a non-finite heading get none."""
    keep = np.isfinite(headings)
    reach = 0.8 * ri
    tips = np.rint(centres[keep] + reach * np.column_stack(
        (np.cos(headings[keep]), -np.sin(headings[keep])))).astype(np.int64)
    width = max(1, ri // 4)
    for start, end in zip(centres[keep].tolist(), tips.tolist(), strict=True):
        pygame.draw.line(surf, HEADING_MARK, start, end, width)


class Renderer:
    """Draws snapshots of one world into RGB frames.

    Args:
        world: the world being simulated (arena, target, spawns, obstacles, beacon).
        grid: the coverage raster whose ``covered`` grids snapshots carry; when None the raster
            geometry is derived from the target's bounding box and the grid's shape (the same
            rule as :meth:`CoverageGrid.for_target`).
        width: frame width in pixels (even, >= 64). The height follows the arena's aspect
            ratio, rounded to a multiple of 16 when ``width`` is one, else to an even number.
        color_by: robot colouring: ``"status"`` or a field of ``colourings``; None: the
            first of ``colourings``, else ``"status"``.
        colourings: the message fields robots may be coloured by, each ``"scale"`` (an
            ordered value such as a hop count; negative values and the field type's largest
            value mean "unknown") or ``"category"`` (such as a group id; 0 or less: none).
            The controller declares them (ControllerInfo.colourings).
        leader_field: a bool message field marking robots drawn with a leader ring, or None.
        group_field: the message field holding a robot's group, or None (the heads-up line
            counts groups; robots that have not broadcast yet show their start group).
        show_coverage: tint covered target pixels (when the snapshot has ``covered``).
        highlight_contacts: draw a red ring around robots in contact.
        legend: draw a legend for the colouring at the bottom.
        hud: draw the heads-up line (tick, coverage, robots on target, groups) at the top.
        on_target: ``f(snapshot) -> int`` counting robots on the target for the heads-up line;
            default: robot centres inside ``world.target`` (shapely.contains_xy).
        min_radius_px: smallest robot disc radius in pixels (robots are tiny at paper scale).
    """

    def __init__(self, world: World, grid: CoverageGrid | None = None, width: int = DEFAULT_WIDTH,
                 color_by: str | None = None, show_coverage: bool = True,
                 highlight_contacts: bool = False, legend: bool = True, *, hud: bool = True,
                 on_target: Callable[[Snapshot], int] | None = None,
                 min_radius_px: float = 2.0, colourings: Mapping[str, str] | None = None,
                 leader_field: str | None = None, group_field: str | None = None):
        self.colourings = dict(colourings or {})
        if color_by is None:
            color_by = next(iter(self.colourings), "status")
        offered = ("status", *self.colourings)
        if color_by not in offered:
            raise ValueError(f"color_by must be one of {', '.join(map(repr, offered))}; "
                             f"got {color_by!r}")
        self.leader_field = leader_field
        self.group_field = group_field
        check_width(width)
        if not min_radius_px > 0:
            raise ValueError(f"min_radius_px must be positive, got {min_radius_px!r}")
        self.world = world
        self.grid = grid
        self.color_by = color_by
        self.show_coverage = bool(show_coverage)
        self.highlight_contacts = bool(highlight_contacts)
        self.legend = bool(legend)
        self.hud = bool(hud)
        self.min_radius_px = float(min_radius_px)
        self._on_target = on_target
        self._target = None  # prepared copy of world.target, made on first use

        xmin, ymin, xmax, ymax = (float(v) for v in world.arena)
        ww, wh = xmax - xmin, ymax - ymin
        width, height = frame_size(world.arena, width)
        self.width, self.height = width, height
        self.wall_px = max(2, width // 400)
        pad = self.wall_px + 1
        self.scale = min((width - 2 * pad) / ww, (height - 2 * pad) / wh)
        # centre the arena in the frame
        self._ox = (width - ww * self.scale) / 2 - xmin * self.scale
        self._oy = (height - wh * self.scale) / 2 + ymax * self.scale

        self._font = self._small_font = None
        try:
            pygame.font.init()
            self._font = pygame.font.Font(None, max(12, round(width / 38)))
            self._small_font = pygame.font.Font(None, max(10, round(width / 42)))
        except (ImportError, NotImplementedError, OSError, RuntimeError, pygame.error):
            # no SDL_ttf or no default font: draw without text
            self._font = self._small_font = None

        self._frame = pygame.Surface((width, height))
        self._background = self._draw_background()
        self._legend_cache: dict[Any, pygame.Surface | None] = {}
        # per covered-grid shape: (left, top, small 32-bit surface, scaled colour-keyed surface)
        self._cover_cache: dict[tuple[int, int], tuple[int, int, pygame.Surface,
                                                       pygame.Surface]] = {}

    # --- geometry ------------------------------------------------------------------------------
    @property
    def size(self) -> tuple[int, int]:
        """(width, height) of the frames in pixels."""
        return self.width, self.height

    @property
    def shape(self) -> tuple[int, int, int]:
        """Shape of the arrays :meth:`draw` returns: (height, width, 3)."""
        return self.height, self.width, 3

    def world_to_pixel(self, xy: Any) -> np.ndarray:
        """World coordinates (..., 2) -> image coordinates (..., 2) as floats (column, row)."""
        xy = np.asarray(xy, dtype=float)
        out = np.empty_like(xy)
        out[..., 0] = self._ox + xy[..., 0] * self.scale
        out[..., 1] = self._oy - xy[..., 1] * self.scale
        return out

    def _ring(self, coords: Any) -> list[tuple[float, float]]:
        return [tuple(p) for p in self.world_to_pixel(np.asarray(coords)[:, :2]).tolist()]

    # --- static background ---------------------------------------------------------------------
    def _draw_background(self) -> pygame.Surface:
        w = self.world
        bg = pygame.Surface((self.width, self.height))
        bg.fill(OUTSIDE)
        (x0, y1), (x1, y0) = self.world_to_pixel([w.arena[:2], w.arena[2:]]).tolist()
        floor = pygame.Rect(round(x0), round(y0), round(x1) - round(x0), round(y1) - round(y0))
        bg.fill(FLOOR, floor)
        pygame.draw.rect(bg, WALL, floor.inflate(2 * self.wall_px, 2 * self.wall_px),
                         width=self.wall_px)
        for poly in shapely.get_parts(w.target):
            pygame.draw.polygon(bg, TARGET_FILL, self._ring(poly.exterior.coords))
            for hole in poly.interiors:
                pygame.draw.polygon(bg, FLOOR, self._ring(hole.coords))
        self._draw_statics(bg)
        return bg

    def _draw_statics(self, bg: pygame.Surface) -> None:
        """Obstacles, spawn outlines, target edges and beacon (redrawn over the coverage tint)."""
        w = self.world
        edge = max(1, self.width // 400)
        for poly in w.obstacles:
            for part in shapely.get_parts(poly):
                pygame.draw.polygon(bg, OBSTACLE_FILL, self._ring(part.exterior.coords))
                pygame.draw.polygon(bg, OBSTACLE_EDGE, self._ring(part.exterior.coords), edge)
        for poly in w.spawns:
            for part in shapely.get_parts(poly):
                pygame.draw.polygon(bg, SPAWN_EDGE, self._ring(part.exterior.coords), 1)
        for poly in shapely.get_parts(w.target):
            pygame.draw.polygon(bg, TARGET_EDGE, self._ring(poly.exterior.coords), edge)
            for hole in poly.interiors:
                pygame.draw.polygon(bg, TARGET_EDGE, self._ring(hole.coords), edge)
        if w.beacon is not None:
            bx, by = self.world_to_pixel(w.beacon).tolist()
            br = max(4, round(self.width / 110))
            for k in range(8):
                ang = k * np.pi / 4
                pygame.draw.line(bg, BEACON_EDGE, (bx, by),
                                 (bx + 1.8 * br * np.cos(ang), by + 1.8 * br * np.sin(ang)), 2)
            pygame.draw.circle(bg, BEACON_FILL, (bx, by), br)
            pygame.draw.circle(bg, BEACON_EDGE, (bx, by), br, 2)

    # --- per-frame layers ----------------------------------------------------------------------
    def _draw_coverage(self, surf: pygame.Surface, covered: np.ndarray) -> None:
        """Paint covered raster cells opaque (colour-keyed blit: ~3x faster than alpha), then
        redraw the static outlines on top so the tint never hides them."""
        covered = np.asarray(covered, dtype=bool)
        if covered.ndim != 2 or covered.size == 0 or not covered.any():
            return
        rows, cols = covered.shape
        cache = self._cover_cache.get((rows, cols))
        if cache is None:
            if self.grid is not None and self.grid.shape == (rows, cols):
                gx0, gy0, gdx, gdy = self.grid.x0, self.grid.y0, self.grid.dx, self.grid.dy
            else:
                bx0, by0, bx1, by1 = self.world.target.bounds
                gx0, gy0, gdx, gdy = bx0, by0, (bx1 - bx0) / cols, (by1 - by0) / rows
            (px0, py0), (px1, py1) = self.world_to_pixel(
                [(gx0, gy0 + rows * gdy), (gx0 + cols * gdx, gy0)]).tolist()
            pw, ph = max(1, round(px1 - px0)), max(1, round(py1 - py0))
            # scaling between surfaces of the frame's own (32-bit) format is ~4x faster than
            # scaling the 24-bit buffer directly
            big = pygame.Surface((pw, ph), 0, surf)
            big.set_colorkey(COLORKEY)
            cache = (round(px0), round(py0), pygame.Surface((cols, rows), 0, surf), big)
            self._cover_cache[(rows, cols)] = cache
        left, top, small32, big = cache
        img = np.where(covered[::-1, :, None], np.uint8(COVER_FILL), np.uint8(COLORKEY))
        small32.blit(pygame.image.frombuffer(img.tobytes(), (cols, rows), "RGB"), (0, 0))
        pygame.transform.scale(small32, big.get_size(), big)  # nearest: crisp raster cells
        surf.blit(big, (left, top))
        self._draw_statics(surf)

    def robot_colors(self, snapshot: Snapshot) -> np.ndarray:
        """(N, 3) uint8 colour of each robot under ``color_by`` (failed robots are drawn dark)."""
        pal, idx = self._color_index(snapshot)
        return pal[idx]

    def _color_index(self, snapshot: Snapshot) -> tuple[np.ndarray, np.ndarray]:
        """(palette (K, 3) uint8, (N,) index into it) for the current ``color_by``."""
        msgs = snapshot.messages
        if snapshot.n_robots == 0:
            return GRADIENT_PALETTE, np.zeros(0, dtype=np.int64)
        kind = self.colourings.get(self.color_by)
        if kind == "scale":
            g, unknown = roles.scale(snapshot, self.color_by)
            pal = np.vstack([GRADIENT_PALETTE, np.uint8(NONE_GREY)])
            idx = np.where((g >= unknown) | (g < 0), len(GRADIENT_PALETTE),
                           g % len(GRADIENT_PALETTE))
        elif kind == "category":
            g = roles.category(snapshot, self.color_by, self.group_field)
            pal = np.vstack([np.uint8(NONE_GREY), GROUP_PALETTE])
            idx = np.where(g <= 0, 0, (g - 1) % len(GROUP_PALETTE) + 1)
        else:
            s = msgs["status"].astype(np.int64)  # -1: nothing heard yet (tick 0)
            pal = np.vstack([STATUS_PALETTE, np.uint8(NONE_GREY)])
            idx = np.where(s < 0, len(STATUS_PALETTE), s % len(STATUS_PALETTE))
        return pal, idx

    def _draw_robots(self, surf: pygame.Surface, snap: Snapshot) -> None:
        n = snap.n_robots
        if n == 0:
            return
        pos = np.asarray(snap.positions, dtype=float).reshape(n, 2)
        ok = np.isfinite(pos).all(axis=1)
        pix = np.rint(self.world_to_pixel(pos))
        lim = 4 * max(self.width, self.height)
        pix = np.clip(np.nan_to_num(pix), -lim, lim).astype(np.int64)
        r = max(self.min_radius_px, float(snap.radius) * self.scale)
        ri = max(1, round(r))
        pal, idx = self._color_index(snap)
        failed = _mask(snap.failed, n)
        leader = roles.leaders(snap, self.leader_field)
        contact = _mask(snap.in_contact, n) if self.highlight_contacts else None

        circle = pygame.draw.circle
        live = ok & ~failed
        # one pass per colour: far fewer Python objects than a colour tuple per robot
        idx = np.where(live, idx, -1)
        for k in np.unique(idx).tolist():
            if k >= 0:
                c = tuple(pal[k].tolist())
                for p in pix[idx == k].tolist():
                    circle(surf, c, p, ri)
        dead = ok & failed
        if dead.any():
            arm = max(1, round(ri * 0.6))
            for x, y in pix[dead].tolist():
                circle(surf, FAILED, (x, y), ri)
                if ri >= 4:
                    pygame.draw.line(surf, FAILED_MARK, (x - arm, y - arm), (x + arm, y + arm))
                    pygame.draw.line(surf, FAILED_MARK, (x - arm, y + arm), (x + arm, y - arm))
        if snap.headings is not None and ri >= HEADING_MIN_PX:
            _draw_heading_marks(surf, pix[live], np.asarray(snap.headings, float)[live], ri)
        ring_w = max(1, ri // 3)
        if contact is not None and contact.any():
            for p in pix[ok & contact].tolist():
                circle(surf, CONTACT_RING, p, ri + 1 + ring_w, ring_w)
        lead = ok & leader
        if lead.any():
            # outside the contact ring when contacts are highlighted
            lr = ri + 1 + ring_w + (1 + ring_w if contact is not None else 0)
            for p in pix[lead].tolist():
                circle(surf, LEADER_RING, p, lr, ring_w)

    def robots_on_target(self, snapshot: Snapshot) -> int:
        """Robots whose centre lies inside the target (or the custom ``on_target`` count)."""
        if self._on_target is not None:
            return int(self._on_target(snapshot))
        if snapshot.n_robots == 0:
            return 0
        if self._target is None:
            self._target = shapely.from_wkb(shapely.to_wkb(self.world.target))
            shapely.prepare(self._target)
        pos = np.asarray(snapshot.positions, dtype=float)
        return int(np.count_nonzero(shapely.contains_xy(self._target, pos[:, 0], pos[:, 1])))

    def hud_text(self, snapshot: Snapshot) -> str:
        """The heads-up line: ``tick T  coverage XX.X %  on target N  groups G`` (groups only
        when the controller broadcasts them; at tick 0 the groups the run started with)."""
        n_groups = roles.group_count(snapshot, self.group_field)
        tail = "" if n_groups is None else f"  groups {n_groups}"
        return (f"tick {snapshot.tick}  coverage {100.0 * snapshot.coverage:.1f} %  "
                f"on target {self.robots_on_target(snapshot)}{tail}")

    def _draw_hud(self, surf: pygame.Surface, snap: Snapshot) -> None:
        if self._font is None:
            return
        text = self._font.render(self.hud_text(snap), True, TEXT)
        m = self._panel_margin
        panel = pygame.Surface((text.get_width() + 2 * m, text.get_height() + m), pygame.SRCALPHA)
        panel.fill(PANEL)
        panel.blit(text, (m, m // 2 + 1))
        surf.blit(panel, (self.wall_px + 2, self.wall_px + 2))

    @property
    def _panel_margin(self) -> int:
        """Padding (pixels) inside the heads-up and legend panels."""
        return max(3, self.width // 160)

    # --- legend --------------------------------------------------------------------------------
    def _legend_key(self, snap: Snapshot) -> Any:
        kind = self.colourings.get(self.color_by)
        leaders = self.leader_field is not None
        if kind == "category":
            g = roles.category(snap, self.color_by, self.group_field)
            return ("category", self.color_by, tuple(int(v) for v in np.unique(g[g > 0])[:11]),
                    leaders)
        if kind == "scale":
            return ("scale", self.color_by, leaders)
        return ("status", tuple(snap.statuses), leaders)

    def _legend_surface(self, snap: Snapshot) -> pygame.Surface | None:
        if self._small_font is None:
            return None
        key = self._legend_key(snap)
        if key not in self._legend_cache:
            margin = self._panel_margin
            max_width = self.width - 2 * (self.wall_px + 2) - 2 * margin
            self._legend_cache[key] = legend_panel(self._small_font, key, max_width, margin,
                                                   self.highlight_contacts)
        return self._legend_cache[key]

    def _draw_legend(self, surf: pygame.Surface, snap: Snapshot) -> None:
        panel = self._legend_surface(snap)
        if panel is not None:
            off = self.wall_px + 2
            surf.blit(panel, (off, self.height - off - panel.get_height()))

    # --- public --------------------------------------------------------------------------------
    def draw_surface(self, snapshot: Snapshot, overlays: bool = True) -> pygame.Surface:
        """Draw ``snapshot`` and return the renderer's own frame Surface (reused next call);
        ``overlays=False`` leaves out the heads-up line and legend (see draw_overlays)."""
        surf = self._frame
        surf.blit(self._background, (0, 0))
        if self.show_coverage and snapshot.covered is not None:
            self._draw_coverage(surf, snapshot.covered)
        self._draw_robots(surf, snapshot)
        if overlays:
            self.draw_overlays(surf, snapshot)
        return surf

    def draw_overlays(self, surf: pygame.Surface, snapshot: Snapshot) -> None:
        """Draw the heads-up line (when ``hud``) and the legend (when ``legend``) of
        ``snapshot`` onto ``surf``, at their places in a frame whose top-left is surf's."""
        if self.hud:
            self._draw_hud(surf, snapshot)
        if self.legend:
            self._draw_legend(surf, snapshot)

    def draw(self, snapshot: Snapshot) -> np.ndarray:
        """Draw ``snapshot``; returns a new (H, W, 3) uint8 RGB array (rows top to bottom).

        The array is read-only (a zero-copy view of the bytes pygame returns); ``.copy()`` it
        to draw on it.
        """
        surf = self.draw_surface(snapshot)
        data = pygame.image.tobytes(surf, "RGB")
        return np.frombuffer(data, dtype=np.uint8).reshape(self.height, self.width, 3)


def _mask(values: Any, n: int) -> np.ndarray:
    if values is None:
        return np.zeros(n, dtype=bool)
    arr = np.asarray(values, dtype=bool).reshape(-1)
    if arr.shape[0] != n:
        raise ValueError(f"expected {n} flags, got {arr.shape[0]}")
    return arr


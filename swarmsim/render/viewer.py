"""A live pygame-ce window on a running Simulation: ``swarmsim view`` and :func:`view`.

The window shows the frame the headless Renderer draws (swarmsim.render.frame) and, on its right,
a panel: the heads-up lines (tick, coverage, robots by status, ticks per second) and the robot
selected with a click (id, status, group, every broadcast field, its last velocity), refreshed
every frame.

Keys: space pauses, ``.`` steps one tick, ``+`` / ``-`` double / halve the ticks per frame, ``c``
cycles the colouring (status and the fields the controller offers), ``o`` toggles the coverage
tint, ``0`` or ``r`` resets the view, ``s`` saves a PNG of the window, ``q`` or closing the
window quits. The mouse wheel zooms about the cursor, a left-button drag pans, a left click
(pressed and released within DRAG_THRESHOLD pixels) selects the robot nearest it.

Events change a frozen :class:`ViewState` through the pure function :func:`handle_event`; the
loop (:class:`Viewer`) only advances the simulation and draws. Viewing never changes the run: it
calls ``Simulation.advance`` like ``run`` does and reads snapshots.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swarmsim.errors import ConfigError

if TYPE_CHECKING:
    import pygame

    from swarmsim.results.snapshot import Snapshot

Simulation = Any  # swarmsim.engine.sim.Simulation: the engine imports render, never the reverse

HEADLESS_ENV = "SWARMSIM_VIEW_HEADLESS"
"""Set to 1 to open the viewer on SDL's dummy video driver (no window; for tests)."""

PANEL_WIDTH = 300  # px, the side panel right of the frame
PANEL_FONT_SIZE = 18  # px, pygame's default font
PANEL_LINES = 24  # the panel's lines other than the broadcast fields (with room to wrap)
HELP_LINES = ("space pause  . step  +/- speed", "c colour  o coverage  s save PNG  q quit",
              "wheel zoom  drag pan  0/r reset view", "click a robot to inspect it")
MAX_TICKS_PER_FRAME = 4096
MAX_ZOOM = 16.0  # the most the camera magnifies the frame
SCREEN_MARGIN = (16, 96)  # px of the screen (across, down) left for window borders, title, task bar
MIN_FITTED_WIDTH = 320  # px, the narrowest frame fitting to a small screen makes
ZOOM_STEP = 1.25  # magnification per notch of the mouse wheel
DRAG_THRESHOLD = 4  # px: a press that moves farther than this pans instead of selecting
FRAMES_PER_SECOND = 30  # the window's redraw cap
NO_DISPLAY = ("no display to open the viewer on (DISPLAY and WAYLAND_DISPLAY are unset): "
              "write a video with 'swarmsim run WORLD --video FILE.mp4', or run the viewer "
              "under a virtual X server: xvfb-run swarmsim view WORLD")


@dataclass(frozen=True)
class Camera:
    """Which part of the Renderer's frame the window shows, magnified.

    The window's frame area is ``size`` (width, height) pixels, the frame's own size. It shows
    the frame around the frame pixel ``centre`` magnified ``zoom`` times (1 to MAX_ZOOM; at 1
    the whole frame, nothing to pan). The view never leaves the frame: ``centre`` is kept at
    least half a window / zoom from the frame's edges. Frame pixels are the Renderer's
    (``Renderer.world_to_pixel``); window pixels count from the window's top-left corner.
    """

    size: tuple[int, int]
    zoom: float
    centre: tuple[float, float]

    @classmethod
    def whole_frame(cls, size: tuple[int, int]) -> Camera:
        """The camera showing the whole frame of ``size`` (width, height) pixels, unmagnified."""
        return cls(size, 1.0, (size[0] / 2, size[1] / 2))

    def __post_init__(self) -> None:
        zoom = min(MAX_ZOOM, max(1.0, float(self.zoom)))
        (w, h), (cx, cy) = self.size, self.centre
        half_w, half_h = w / (2 * zoom), h / (2 * zoom)
        object.__setattr__(self, "zoom", zoom)
        object.__setattr__(self, "centre", (min(w - half_w, max(half_w, float(cx))),
                                            min(h - half_h, max(half_h, float(cy)))))

    @property
    def top_left(self) -> tuple[float, float]:
        """The frame pixel shown at the window's top-left corner."""
        (cx, cy), (w, h) = self.centre, self.size
        return cx - w / (2 * self.zoom), cy - h / (2 * self.zoom)

    def to_window(self, frame_px: Any) -> np.ndarray:
        """Frame pixels (..., 2) -> window pixels (..., 2), floats."""
        return (np.asarray(frame_px, dtype=float) - self.top_left) * self.zoom

    def to_frame(self, window_px: Any) -> np.ndarray:
        """Window pixels (..., 2) -> frame pixels (..., 2), floats."""
        return np.asarray(window_px, dtype=float) / self.zoom + self.top_left

    def contains(self, window_px: tuple[int, int]) -> bool:
        """Whether ``window_px`` lies on the frame area (not on the panel)."""
        return 0 <= window_px[0] < self.size[0] and 0 <= window_px[1] < self.size[1]

    def zoomed(self, factor: float, about: tuple[int, int]) -> Camera:
        """The camera magnified ``factor`` times more, the frame pixel under the window pixel
        ``about`` staying under it (unless the view would leave the frame)."""
        fixed = self.to_frame(about)
        zoom = min(MAX_ZOOM, max(1.0, self.zoom * factor))
        w, h = self.size
        centre = fixed - (np.asarray(about, dtype=float) - (w / 2, h / 2)) / zoom
        return Camera(self.size, zoom, (float(centre[0]), float(centre[1])))

    def panned(self, by: tuple[float, float]) -> Camera:
        """The camera after the picture was dragged ``by`` window pixels (dx, dy)."""
        cx, cy = self.centre
        return Camera(self.size, self.zoom, (cx - by[0] / self.zoom, cy - by[1] / self.zoom))


@dataclass(frozen=True)
class ViewState:
    """What the user asked the viewer for; changed only by :func:`handle_event`.

    Attributes:
        colourings: the colourings ``c`` cycles through ("status" and the controller's fields).
        colour: index into ``colourings`` of the one in use.
        paused: no ticks run while True (``.`` still steps).
        ticks_per_frame: ticks run between two drawn frames while not paused (1..4096).
        steps: ticks still to run while paused (``.`` adds one).
        selected: index of the robot shown in the panel, or None.
        coverage: tint the covered target pixels (``o`` toggles it).
        save: a PNG of the window is wanted (the loop clears it once saved).
        quit: the window should close.
        camera: the part of the frame shown and its magnification (wheel, drag, ``0``/``r``).
        pointer: the last window pixel the mouse was seen at (the wheel zooms about it).
        pressed: where the left button went down on the frame, while it is held; None
            otherwise (or when it went down on the panel).
        dragging: the held button has moved more than DRAG_THRESHOLD pixels: it pans, and its
            release selects nothing.
    """

    colourings: tuple[str, ...]
    camera: Camera
    colour: int = 0
    paused: bool = False
    ticks_per_frame: int = 1
    steps: int = 0
    selected: int | None = None
    coverage: bool = True
    save: bool = False
    quit: bool = False
    pointer: tuple[int, int] = (0, 0)
    pressed: tuple[int, int] | None = None
    dragging: bool = False

    @property
    def color_by(self) -> str:
        return self.colourings[self.colour]


def initial_state(colourings: tuple[str, ...], color_by: str | None,
                  frame_size: tuple[int, int]) -> ViewState:
    """The state a viewer starts in, colouring by ``color_by`` (None: the first offered), the
    whole frame (``frame_size`` (width, height) pixels) in view."""
    colour = colourings.index(color_by) if color_by in colourings else 0
    return ViewState(colourings=colourings, colour=colour, camera=Camera.whole_frame(frame_size))


def handle_event(state: ViewState, event: Any,
                 pick: Callable[[np.ndarray], int | None]) -> ViewState:
    """The state after one pygame ``event``; ``pick(frame_px)`` names the robot nearest the
    frame pixel (float (x, y)) a click on the frame landed on, or None. Events the viewer
    ignores return ``state`` itself."""
    import pygame

    if event.type == pygame.QUIT:
        return dataclasses.replace(state, quit=True)
    if event.type in (pygame.MOUSEBUTTONDOWN, pygame.MOUSEBUTTONUP, pygame.MOUSEMOTION,
                      pygame.MOUSEWHEEL):
        return _mouse_event(state, event, pick)
    if event.type != pygame.KEYDOWN:
        return state
    key, text = event.key, getattr(event, "unicode", "")
    if key == pygame.K_q or key == pygame.K_ESCAPE:
        return dataclasses.replace(state, quit=True)
    if key == pygame.K_SPACE:
        return dataclasses.replace(state, paused=not state.paused, steps=0)
    if key == pygame.K_PERIOD:
        return dataclasses.replace(state, paused=True, steps=state.steps + 1)
    if key in (pygame.K_PLUS, pygame.K_KP_PLUS, pygame.K_EQUALS) or text == "+":
        return dataclasses.replace(state, ticks_per_frame=min(MAX_TICKS_PER_FRAME,
                                                              state.ticks_per_frame * 2))
    if key in (pygame.K_MINUS, pygame.K_KP_MINUS) or text == "-":
        return dataclasses.replace(state, ticks_per_frame=max(1, state.ticks_per_frame // 2))
    if key == pygame.K_c:
        return dataclasses.replace(state, colour=(state.colour + 1) % len(state.colourings))
    if key == pygame.K_o:
        return dataclasses.replace(state, coverage=not state.coverage)
    if key == pygame.K_s:
        return dataclasses.replace(state, save=True)
    if key in (pygame.K_0, pygame.K_KP_0, pygame.K_r):
        return dataclasses.replace(state, camera=Camera.whole_frame(state.camera.size))
    return state


def _mouse_event(state: ViewState, event: Any,
                 pick: Callable[[np.ndarray], int | None]) -> ViewState:
    """handle_event for the mouse: the wheel zooms about the pointer, a left-button drag on the
    frame pans, a left click on the frame (released within DRAG_THRESHOLD px) selects."""
    import pygame

    if event.type == pygame.MOUSEWHEEL:
        factor = ZOOM_STEP ** float(getattr(event, "precise_y", event.y))
        if getattr(event, "flipped", False):
            factor = 1 / factor
        if factor == 1 or not state.camera.contains(state.pointer):
            return state
        return dataclasses.replace(state, camera=state.camera.zoomed(factor, state.pointer))
    pos = (int(event.pos[0]), int(event.pos[1]))
    if event.type == pygame.MOUSEMOTION:
        if state.pressed is None:
            return dataclasses.replace(state, pointer=pos)
        moved = (pos[0] - state.pointer[0], pos[1] - state.pointer[1])
        if not state.dragging:
            far = np.hypot(pos[0] - state.pressed[0], pos[1] - state.pressed[1])
            if far <= DRAG_THRESHOLD:
                return state  # still a click: the pointer stays where the button went down
            moved = (pos[0] - state.pressed[0], pos[1] - state.pressed[1])
        return dataclasses.replace(state, pointer=pos, dragging=True,
                                   camera=state.camera.panned(moved))
    if event.button != 1:
        return dataclasses.replace(state, pointer=pos)
    if event.type == pygame.MOUSEBUTTONDOWN:
        pressed = pos if state.camera.contains(pos) else None
        return dataclasses.replace(state, pointer=pos, pressed=pressed, dragging=False)
    # MOUSEBUTTONUP: a click when the button did not move far since it went down on the frame
    after = dataclasses.replace(state, pointer=pos, pressed=None, dragging=False)
    if state.pressed is None or state.dragging:
        return after
    return dataclasses.replace(after, selected=pick(state.camera.to_frame(state.pressed)))


def nearest_robot(points: np.ndarray, at: Any) -> int | None:
    """Index of the row of ``points`` ((N, 2) robot centres) nearest ``at`` (x, y) in the same
    coordinates, or None when there are no robots."""
    if len(points) == 0:
        return None
    d2 = np.sum((np.asarray(points, dtype=float) - np.asarray(at, dtype=float)) ** 2, axis=1)
    return int(np.argmin(d2))


def frame_to_world(renderer: Any, frame_px: Any) -> np.ndarray:
    """Frame pixels (..., 2) -> world coordinates (..., 2): the inverse of the Renderer's
    ``world_to_pixel`` (``scale`` pixels per unit, y flipped)."""
    origin = renderer.world_to_pixel((0.0, 0.0))
    offset = (np.asarray(frame_px, dtype=float) - origin) / renderer.scale
    return offset * (1.0, -1.0)


def display_problem(environ: os._Environ[str] | dict[str, str], platform: str) -> str | None:
    """Why no window can open (the NO_DISPLAY line), or None. Only Linux and the BSDs are
    checked (X11 or Wayland must be named); the headless flag (HEADLESS_ENV=1) always passes."""
    if environ.get(HEADLESS_ENV) == "1":
        return None
    x11_or_wayland = platform.startswith(("linux", "freebsd", "openbsd", "netbsd"))
    if x11_or_wayland and not environ.get("DISPLAY") and not environ.get("WAYLAND_DISPLAY"):
        return NO_DISPLAY
    return None


def in_range(positions: np.ndarray, failed: np.ndarray, robot: int, reach: float
             ) -> np.ndarray:
    """Indices of the robots other than ``robot`` whose centres lie within ``reach`` (units,
    the robot's listening range) of it and that have not failed: those whose broadcasts it
    can hear (a message lost to noise is not known here)."""
    d2 = np.sum((positions - positions[robot]) ** 2, axis=1)
    near = (d2 <= reach * reach) & ~failed
    near[robot] = False
    return np.flatnonzero(near)


def _status_counts(snapshot: Snapshot) -> str:
    """``NAME n`` for each status robots have, silent robots as ``unheard``."""
    codes = np.asarray(snapshot.messages["status"])
    names = snapshot.statuses
    parts = []
    for code, count in zip(*np.unique(codes, return_counts=True), strict=True):
        name = names[code] if 0 <= code < len(names) else "unheard"
        parts.append(f"{name} {count}")
    return ", ".join(parts)


def robot_lines(snapshot: Snapshot, robot: int, velocity: np.ndarray | None,
                group_field: str | None, asleep: bool | None = None) -> list[str]:
    """The panel's lines about ``robot``: id, status name, group, asleep or awake (when
    ``asleep`` is known), its last commanded velocity (units per tick) and every broadcast
    field."""
    row = snapshot.messages[robot]
    code = int(row["status"])
    status = snapshot.statuses[code] if 0 <= code < len(snapshot.statuses) else "unheard"
    lines = [f"robot {robot}", f"status {status}"]
    if group_field and group_field in row.dtype.names:
        lines.append(f"group {row[group_field]}")
    elif snapshot.start_groups is not None:
        lines.append(f"group {int(snapshot.start_groups[robot])} (start)")
    if snapshot.failed[robot]:
        lines.append("FAILED")
    if asleep is not None:
        lines.append("asleep" if asleep else "awake")
    x, y = snapshot.positions[robot]
    lines.append(f"at ({x:.2f}, {y:.2f})")
    if velocity is not None:
        lines.append(f"velocity ({velocity[0]:+.3f}, {velocity[1]:+.3f})")
    lines.append("broadcast:")
    for name in row.dtype.names:
        if np.size(row[name]):  # a field of no elements (one per group of none) says nothing
            lines.append(f"  {name} = {_shown(row[name])}")
    return lines


def _shown(value: Any) -> str:
    """A broadcast field's value as the panel shows it (floats to 4 significant digits)."""
    arr = np.asarray(value)
    if np.issubdtype(arr.dtype, np.floating):
        return np.array2string(arr, precision=4) if arr.ndim else f"{float(arr):.4g}"
    return str(arr.tolist())


class Viewer:
    """A window on ``sim``: call :meth:`frame` repeatedly (or :meth:`loop`).

    Args:
        sim: the simulation to run and show (it may already have run some ticks).
        width: frame width in pixels (the Renderer's rule: even, >= 64); None: the
            Renderer's DEFAULT_WIDTH, or less so that the window fits the screen
            (:func:`fitted_width`).
        color_by: the colouring to start with (None: the controller's first).
        save_dir: folder the ``s`` key saves PNGs into (``view-tick{T}.png``).
        on_tick: called after every tick the viewer runs, as ``Simulation.run``'s on_tick
            (a recorder's, to keep what ``swarmsim replay`` needs).
    Raises ConfigError (the NO_DISPLAY line) when there is no display to open a window on.
    """

    def __init__(self, sim: Simulation, width: int | None = None, color_by: str | None = None,
                 save_dir: str | os.PathLike[str] = ".",
                 on_tick: Callable[[Simulation], None] | None = None):
        problem = display_problem(os.environ, sys.platform)
        if problem:
            raise ConfigError(problem)
        offered = sim.offered_colourings(color_by)
        self.sim = sim
        self.on_tick = on_tick
        if width is None:
            width = fitted_width(sim.world.arena, _screen_size())
        self.renderer = sim.new_renderer(width=width, color_by=color_by)
        self.state = initial_state(offered, self.renderer.color_by, self.renderer.size)
        self.save_dir = Path(save_dir)
        self.saved: list[Path] = []
        import pygame

        pygame.font.init()
        self._font = pygame.font.Font(None, PANEL_FONT_SIZE)
        # tall enough for the panel with every broadcast field of a selected robot
        panel_height = 16 + self._font.get_linesize() * (PANEL_LINES
                                                         + len(sim.messages.dtype.names))
        self._window = _open_window(self.renderer.width + PANEL_WIDTH,
                                    max(self.renderer.height, panel_height))
        self._clock = pygame.time.Clock()
        self._rate: tuple[float, int] = (time.perf_counter(), sim.tick)
        self.ticks_per_second = 0.0
        self.frames = 0

    # --- one frame --------------------------------------------------------------------------
    def pick(self, frame_px: np.ndarray) -> int | None:
        """The robot whose centre is nearest, in world units, the point drawn at the frame
        pixel ``frame_px`` (x, y), or None when there are no robots."""
        return nearest_robot(self.sim.positions, frame_to_world(self.renderer, frame_px))

    def handle(self, events: list[Any]) -> None:
        """Apply ``events`` to the state (see :func:`handle_event`)."""
        for event in events:
            self.state = handle_event(self.state, event, self.pick)

    def advance(self) -> None:
        """Run the ticks the state asks for (none once the run has stopped)."""
        sim, state = self.sim, self.state
        ticks = state.steps if state.paused else state.ticks_per_frame
        for _ in range(ticks):
            if sim.stop_reason is not None:
                break
            sim.advance(self.on_tick)
        if state.steps:
            self.state = dataclasses.replace(state, steps=0)

    def frame(self) -> bool:
        """Handle pending events, advance, draw; False once the viewer should close."""
        import pygame

        self.handle(pygame.event.get())
        if self.state.quit:
            return False
        self.advance()
        self.draw()
        if self.state.save:
            self.save_png()
            self.state = dataclasses.replace(self.state, save=False)
        self.frames += 1
        return True

    def loop(self, max_frames: int | None = None) -> None:
        """Show frames until ``q`` or the window closes (or ``max_frames`` frames)."""
        while (max_frames is None or self.frames < max_frames) and self.frame():
            self._clock.tick(FRAMES_PER_SECOND)

    # --- drawing ----------------------------------------------------------------------------
    def draw(self) -> None:
        import pygame

        self.renderer.color_by = self.state.color_by
        self.renderer.show_coverage = self.state.coverage
        snap = self.sim.snapshot(with_coverage=self.state.coverage)
        camera = self.state.camera
        self._window.fill((24, 24, 28))
        self._window.set_clip(pygame.Rect((0, 0), camera.size))
        if camera.zoom == 1:
            self._window.blit(self.renderer.draw_surface(snap), (0, 0))
        else:  # magnify the frame's part in view; the heads-up line and legend stay unscaled
            _blit_magnified(self._window, self.renderer.draw_surface(snap, overlays=False),
                            camera)
            self.renderer.draw_overlays(self._window, snap)
        if self.state.selected is not None and self.state.selected < snap.n_robots:
            self._draw_selection(snap, self.state.selected, camera)
        self._window.set_clip(None)
        self._draw_panel(snap)
        pygame.display.flip()

    def _draw_selection(self, snap: Snapshot, robot: int, camera: Camera) -> None:
        """A ring around ``robot`` and a line to each robot it hears, in window pixels."""
        import pygame

        def window_px(world: np.ndarray) -> np.ndarray:
            return camera.to_window(self.renderer.world_to_pixel(world))

        p = window_px(snap.positions[robot])
        centre = (float(p[0]), float(p[1]))
        r = max(10.0, snap.radius * self.renderer.scale * camera.zoom * 3)
        heard = in_range(snap.positions, snap.failed, robot, float(self.sim.listen[robot]))
        for q in window_px(snap.positions[heard]):
            pygame.draw.line(self._window, (255, 140, 0), centre, (float(q[0]), float(q[1])))
        pygame.draw.circle(self._window, (0, 0, 0), centre, r + 2, 2)
        pygame.draw.circle(self._window, (255, 200, 0), centre, r, 3)

    def panel_lines(self, snap: Snapshot) -> list[str]:
        """The side panel's text: heads-up lines, then the selected robot's."""
        now = time.perf_counter()
        t0, tick0 = self._rate
        if now - t0 >= 0.5:
            self.ticks_per_second = (snap.tick - tick0) / (now - t0)
            self._rate = (now, snap.tick)
        state, sim = self.state, self.sim
        run = ("finished: " + sim.stop_reason if sim.stop_reason
               else "paused" if state.paused else "running")
        lines = [f"tick {snap.tick}   coverage {100 * snap.coverage:.1f} %",
                 f"{run}   {self.ticks_per_second:.0f} ticks/s",
                 f"ticks per frame {state.ticks_per_frame}   zoom {state.camera.zoom:.2g}x",
                 f"colour by {state.color_by}",
                 f"robots: {_status_counts(snap)}", "", *HELP_LINES, ""]
        if state.selected is not None and state.selected < snap.n_robots:
            robot = state.selected
            lines += robot_lines(snap, robot, sim.velocities[robot], sim.info.group_field,
                                 bool(sim.asleep[robot]))
            heard = in_range(snap.positions, snap.failed, robot, float(sim.listen[robot]))
            lines.insert(lines.index("broadcast:"),
                         f"hears {len(heard)} (range {sim.listen[robot]:.3g})")
        return lines

    def _draw_panel(self, snap: Snapshot) -> None:
        x0, y = self.renderer.width + 8, 8
        height = self._font.get_linesize()
        for line in self.panel_lines(snap):
            for part in _wrap(line, PANEL_WIDTH - 16, self._font):
                self._window.blit(self._font.render(part, True, (230, 230, 230)), (x0, y))
                y += height

    def save_png(self) -> Path:
        """Save the window as ``save_dir/view-tick{T}.png``; returns the path."""
        import pygame

        from swarmsim.render.video import save_png

        w, h = self._window.get_size()
        rgb = np.frombuffer(pygame.image.tobytes(self._window, "RGB"), np.uint8)
        path = save_png(rgb.reshape(h, w, 3), self.save_dir / f"view-tick{self.sim.tick}.png")
        self.saved.append(path)
        return path

    def close(self) -> None:
        import pygame

        pygame.display.quit()


def _blit_magnified(window: pygame.Surface, frame: pygame.Surface, camera: Camera) -> None:
    """Draw the part of ``frame`` the camera sees onto ``window``'s frame area, magnified:
    the whole frame pixels covering the view, scaled (nearest neighbour) by the zoom and
    placed so frame pixel f lands at ``camera.to_window(f)`` (within a window pixel)."""
    import math

    import pygame

    (left, top), zoom = camera.top_left, camera.zoom
    w, h = camera.size
    x0, y0 = math.floor(left), math.floor(top)
    x1, y1 = min(w, math.ceil(left + w / zoom)), min(h, math.ceil(top + h / zoom))
    part = frame.subsurface(pygame.Rect(x0, y0, x1 - x0, y1 - y0))
    scaled = pygame.transform.scale(part, (round((x1 - x0) * zoom), round((y1 - y0) * zoom)))
    window.blit(scaled, (round((x0 - left) * zoom), round((y0 - top) * zoom)))


def _wrap(line: str, width: int, font: Any) -> list[str]:
    """``line`` broken at spaces into parts at most ``width`` px wide in ``font``."""
    indent = line[:len(line) - len(line.lstrip(" "))]
    parts: list[str] = []
    current = ""
    for word in line.lstrip(" ").split(" "):
        trial = word if not current else f"{current} {word}"
        if current and font.size(trial)[0] > width:
            parts.append(current)
            current = word
        else:
            current = trial
    parts.append(current)
    parts[0] = indent + parts[0]
    return parts


def fitted_width(arena: tuple[float, float, float, float], screen: tuple[int, int] | None,
                 wanted: int | None = None) -> int:
    """The frame width, ``wanted`` px (None: the Renderer's DEFAULT_WIDTH) or less (even, at least MIN_FITTED_WIDTH), at which
    the viewer's window (the frame of ``arena`` and the panel) fits a ``screen`` of (width,
    height) px less SCREEN_MARGIN; ``wanted`` when the screen is unknown (None)."""
    from swarmsim.render.frame import DEFAULT_WIDTH
    from swarmsim.render.frame import frame_size as frame_px

    wanted = DEFAULT_WIDTH if wanted is None else wanted
    if screen is None:
        return wanted
    room_w, room_h = screen[0] - SCREEN_MARGIN[0] - PANEL_WIDTH, screen[1] - SCREEN_MARGIN[1]
    width = wanted
    while width > MIN_FITTED_WIDTH:
        frame_w, frame_h = frame_px(arena, width)
        if frame_w <= room_w and frame_h <= room_h:
            break
        width -= 16
    return max(width, MIN_FITTED_WIDTH)


def _screen_size() -> tuple[int, int] | None:
    """The desktop's size in px (the first display's), or None under HEADLESS_ENV or when SDL
    cannot tell."""
    if os.environ.get(HEADLESS_ENV) == "1":
        return None
    _choose_video_driver()
    import pygame

    try:
        pygame.display.init()
        sizes = pygame.display.get_desktop_sizes()
    except pygame.error:
        return None
    return tuple(sizes[0]) if sizes else None  # type: ignore[return-value]


def _choose_video_driver() -> None:
    """SDL's dummy driver under HEADLESS_ENV=1, else SDL's own choice."""
    # swarmsim.render.frame sets SDL_VIDEODRIVER=dummy for headless frames unless the user
    # chose a driver: a real window needs SDL's own choice back
    if os.environ.get(HEADLESS_ENV) == "1":
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    elif os.environ.get("SDL_VIDEODRIVER") == "dummy":
        del os.environ["SDL_VIDEODRIVER"]


def _open_window(width: int, height: int) -> pygame.Surface:
    """Open the window; under HEADLESS_ENV=1 on SDL's dummy driver. ConfigError if SDL cannot
    open one."""
    _choose_video_driver()
    import pygame

    pygame.display.init()
    pygame.font.init()
    try:
        window = pygame.display.set_mode((width, height))
    except pygame.error as exc:
        raise ConfigError(f"cannot open the viewer's window ({exc}): write a video with "
                          "'swarmsim run WORLD --video FILE.mp4', or run the viewer under "
                          "xvfb-run") from None
    pygame.display.set_caption("swarmsim")
    return window


def view(sim: Simulation, width: int | None = None, color_by: str | None = None,
         max_frames: int | None = None,
         on_tick: Callable[[Simulation], None] | None = None) -> Viewer:
    """Open a window on ``sim`` and run it live until the user quits (or ``max_frames``
    frames are shown), calling ``on_tick`` after each tick; returns the closed Viewer (its
    ``saved`` PNGs, ``frames``)."""
    viewer = Viewer(sim, width=width, color_by=color_by, on_tick=on_tick)
    try:
        viewer.loop(max_frames)
    finally:
        viewer.close()
    return viewer

"""A live pygame-ce window on a running Simulation: ``swarmsim view`` and :func:`view`.

The window shows the frame the headless Renderer draws (swarmsim.render.frame) and, on its right,
a panel: the heads-up lines (tick, coverage, robots by status, ticks per second) and the robot
selected with a click (id, status, group, every broadcast field, its last velocity), refreshed
every frame.

Keys: space pauses, ``.`` steps one tick, ``+`` / ``-`` double / halve the ticks per frame, ``c``
cycles the colouring (status and the fields the controller offers), ``o`` toggles the coverage
tint, ``s`` saves a PNG of the
window, ``q`` or closing the window quits.

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
MAX_TICKS_PER_FRAME = 4096
FRAMES_PER_SECOND = 30  # the window's redraw cap
NO_DISPLAY = ("no display to open the viewer on (DISPLAY and WAYLAND_DISPLAY are unset): "
              "write a video with 'swarmsim run WORLD --video FILE.mp4', or run the viewer "
              "under a virtual X server: xvfb-run swarmsim view WORLD")


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
    """

    colourings: tuple[str, ...]
    colour: int = 0
    paused: bool = False
    ticks_per_frame: int = 1
    steps: int = 0
    selected: int | None = None
    coverage: bool = True
    save: bool = False
    quit: bool = False

    @property
    def color_by(self) -> str:
        return self.colourings[self.colour]


def initial_state(colourings: tuple[str, ...], color_by: str | None) -> ViewState:
    """The state a viewer starts in, colouring by ``color_by`` (None: the first offered)."""
    colour = colourings.index(color_by) if color_by in colourings else 0
    return ViewState(colourings=colourings, colour=colour)


def handle_event(state: ViewState, event: Any,
                 pick: Callable[[tuple[int, int]], int | None]) -> ViewState:
    """The state after one pygame ``event``; ``pick(pixel)`` names the robot nearest a click
    on the frame (None: the click was not on the frame). Events the viewer ignores return
    ``state`` itself."""
    import pygame

    if event.type == pygame.QUIT:
        return dataclasses.replace(state, quit=True)
    if event.type == pygame.MOUSEBUTTONDOWN and event.button == 1:
        return dataclasses.replace(state, selected=pick(tuple(event.pos)))
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
    return state


def nearest_robot(pixels: np.ndarray, at: tuple[float, float]) -> int | None:
    """Index of the row of ``pixels`` ((N, 2) robot centres in window pixels) nearest ``at``,
    or None when there are no robots."""
    if len(pixels) == 0:
        return None
    d2 = np.sum((np.asarray(pixels, dtype=float) - np.asarray(at, dtype=float)) ** 2, axis=1)
    return int(np.argmin(d2))


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
        width: frame width in pixels (the Renderer's rule: even, >= 64).
        color_by: the colouring to start with (None: the controller's first).
        save_dir: folder the ``s`` key saves PNGs into (``view-tick{T}.png``).
    Raises ConfigError (the NO_DISPLAY line) when there is no display to open a window on.
    """

    def __init__(self, sim: Simulation, width: int = 800, color_by: str | None = None,
                 save_dir: str | os.PathLike[str] = "."):
        problem = display_problem(os.environ, sys.platform)
        if problem:
            raise ConfigError(problem)
        offered = sim.offered_colourings(color_by)
        self.sim = sim
        self.renderer = sim.new_renderer(width=width, color_by=color_by)
        self.state = initial_state(offered, self.renderer.color_by)
        self.save_dir = Path(save_dir)
        self.saved: list[Path] = []
        self._window = _open_window(self.renderer.width + PANEL_WIDTH, self.renderer.height)
        import pygame

        self._font = pygame.font.Font(None, 18)
        self._clock = pygame.time.Clock()
        self._rate: tuple[float, int] = (time.perf_counter(), sim.tick)
        self.ticks_per_second = 0.0
        self.frames = 0

    # --- one frame --------------------------------------------------------------------------
    def pick(self, pixel: tuple[int, int]) -> int | None:
        """The robot nearest ``pixel`` of the window, or None outside the frame."""
        if not (0 <= pixel[0] < self.renderer.width and 0 <= pixel[1] < self.renderer.height):
            return self.state.selected
        return nearest_robot(self.renderer.world_to_pixel(self.sim.positions), pixel)

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
            sim.advance()
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
        surf = self.renderer.draw_surface(snap)
        self._window.fill((24, 24, 28))
        self._window.blit(surf, (0, 0))
        if self.state.selected is not None and self.state.selected < snap.n_robots:
            p = self.renderer.world_to_pixel(snap.positions[self.state.selected])
            centre, r = (float(p[0]), float(p[1])), max(10.0, snap.radius * self.renderer.scale * 3)
            heard = in_range(snap.positions, snap.failed, self.state.selected,
                             float(self.sim.listen[self.state.selected]))
            for q in self.renderer.world_to_pixel(snap.positions[heard]):
                pygame.draw.line(self._window, (255, 140, 0), centre, (float(q[0]), float(q[1])))
            pygame.draw.circle(self._window, (0, 0, 0), centre, r + 2, 2)
            pygame.draw.circle(self._window, (255, 200, 0), centre, r, 3)
        self._draw_panel(snap)
        pygame.display.flip()

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
                 f"ticks per frame {state.ticks_per_frame}",
                 f"colour by {state.color_by}",
                 f"robots: {_status_counts(snap)}", ""]
        if state.selected is not None and state.selected < snap.n_robots:
            robot = state.selected
            lines += robot_lines(snap, robot, sim.velocities[robot], sim.info.group_field,
                                 bool(sim.asleep[robot]))
            heard = in_range(snap.positions, snap.failed, robot, float(sim.listen[robot]))
            lines.insert(-len(snap.messages.dtype.names) - 1,
                         f"hears {len(heard)} (range {sim.listen[robot]:.3g})")
        else:
            lines.append("click a robot to inspect it")
        lines += ["", "space pause  . step  +/- speed", "c colour  o coverage  s save PNG  q quit"]
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


def _open_window(width: int, height: int) -> pygame.Surface:
    """Open the window; under HEADLESS_ENV=1 on SDL's dummy driver. ConfigError if SDL cannot
    open one."""
    # swarmsim.render.frame sets SDL_VIDEODRIVER=dummy for headless frames unless the user
    # chose a driver: a real window needs SDL's own choice back
    if os.environ.get(HEADLESS_ENV) == "1":
        os.environ["SDL_VIDEODRIVER"] = "dummy"
    elif os.environ.get("SDL_VIDEODRIVER") == "dummy":
        del os.environ["SDL_VIDEODRIVER"]
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


def view(sim: Simulation, width: int = 800, color_by: str | None = None,
         max_frames: int | None = None) -> Viewer:
    """Open a window on ``sim`` and run it live until the user quits (or ``max_frames``
    frames are shown); returns the closed Viewer (its ``saved`` PNGs, ``frames``)."""
    viewer = Viewer(sim, width=width, color_by=color_by)
    try:
        viewer.loop(max_frames)
    finally:
        viewer.close()
    return viewer

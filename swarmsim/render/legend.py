"""The frame's legend: what the robots' colours, rings and marks mean, in rows that wrap at
the frame's width. Built once per colouring key and cached by the renderer."""

from __future__ import annotations

from typing import Any

import pygame
import pygame.font

from swarmsim.render.palette import (
    CONTACT_RING,
    FAILED,
    FAILED_MARK,
    GRADIENT_PALETTE,
    GROUP_PALETTE,
    LEADER_RING,
    NONE_GREY,
    PANEL,
    STATUS_PALETTE,
    TEXT,
)

MAX_GROUPS_LISTED = 10


def legend_panel(font: pygame.font.Font, key: tuple, max_width: int, margin: int,
                 contacts: bool) -> pygame.Surface:
    """The legend for colouring ``key`` (``("scale", field, leaders)``, ``("category", field,
    ids, leaders)`` or ``("status", names, leaders)``; leaders: draw the leader mark), at most
    ``max_width`` pixels wide plus ``margin`` on each side; ``contacts`` adds the contact
    ring."""
    gap = max(3, font.get_linesize() // 3)
    return _flow(_items(font, key, contacts), max_width, margin, gap)


def _swatch_size(font: pygame.font.Font) -> int:
    return max(6, font.get_linesize() - 4)


def _label(font: pygame.font.Font, text: str) -> pygame.Surface:
    return font.render(text, True, TEXT)


def _items(font: pygame.font.Font, key: tuple, contacts: bool) -> list[pygame.Surface]:
    """The legend's entries, left to right: the colouring's name, its colours, the marks."""
    kind = key[0]
    items = [_label(font, f"{'status' if kind == 'status' else key[1]}:")]
    if kind == "scale":
        items.append(_gradient_strip(font))
    elif kind == "status":
        items += [_swatch(font, "disc", tuple(STATUS_PALETTE[i % len(STATUS_PALETTE)]), str(name))
                  for i, name in enumerate(key[1])]
        items.append(_swatch(font, "disc", NONE_GREY, "none"))  # nothing broadcast yet
    else:
        items.append(_swatch(font, "disc", NONE_GREY, "none"))
        ids = key[2]
        items += [_swatch(font, "disc", tuple(GROUP_PALETTE[(g - 1) % len(GROUP_PALETTE)]), str(g))
                  for g in ids[:MAX_GROUPS_LISTED]]
        if len(ids) > MAX_GROUPS_LISTED:
            items.append(_label(font, "..."))
    dot = _sample_color(key)  # leaders and touching robots: a robot's disc with a ring
    if key[-1]:  # the controller marks leaders
        items.append(_swatch(font, "ringed", LEADER_RING, "leader", dot))
    items.append(_swatch(font, "failed", FAILED, "failed"))
    if contacts:
        items.append(_swatch(font, "ringed", CONTACT_RING, "contact", dot))
    return items


def _sample_color(key: tuple) -> tuple[int, int, int]:
    """A robot colour of the colouring ``key`` for the ringed swatches: gradient 0 (a
    leader's own), group 1 or the first status."""
    if key[0] == "scale":
        return tuple(GRADIENT_PALETTE[0].tolist())
    if key[0] == "status":
        return tuple(STATUS_PALETTE[0].tolist())
    return tuple(GROUP_PALETTE[0].tolist())


def _swatch(font: pygame.font.Font, kind: str, color: Any, text: str,
            fill: Any = NONE_GREY) -> pygame.Surface:
    """A disc of ``color``, a ``fill`` disc ringed in ``color`` ("ringed", as the frame draws
    leaders and touching robots) or a failed-robot mark, followed by ``text``."""
    sw = _swatch_size(font)
    lab = _label(font, text)
    s = pygame.Surface((sw + 3 + lab.get_width(), max(sw, lab.get_height())), pygame.SRCALPHA)
    c = (sw // 2, s.get_height() // 2)
    rad = sw // 2
    if kind == "disc":
        pygame.draw.circle(s, color, c, rad)
    elif kind == "ringed":
        ring_w = max(1, sw // 6)
        pygame.draw.circle(s, fill, c, max(1, rad - ring_w - 1))
        pygame.draw.circle(s, color, c, rad, ring_w)
    elif kind == "failed":
        pygame.draw.circle(s, FAILED, c, rad)
        a = max(1, rad // 2)
        pygame.draw.line(s, FAILED_MARK, (c[0] - a, c[1] - a), (c[0] + a, c[1] + a))
        pygame.draw.line(s, FAILED_MARK, (c[0] - a, c[1] + a), (c[0] + a, c[1] - a))
    s.blit(lab, (sw + 3, (s.get_height() - lab.get_height()) // 2))
    return s


def _gradient_strip(font: pygame.font.Font) -> pygame.Surface:
    """The gradient palette's cells numbered 0..13, then grey for "inf" (no gradient)."""
    fh = font.get_linesize()
    cell = max(font.size("13")[0] + 4, _swatch_size(font))
    strip = pygame.Surface((cell * (len(GRADIENT_PALETTE) + 1) + 1, fh), pygame.SRCALPHA)
    colors = [*map(tuple, GRADIENT_PALETTE.tolist()), NONE_GREY]
    for i, c in enumerate(colors):
        rect = pygame.Rect(i * cell, 0, cell - 1, fh)
        strip.fill(c, rect)
        lum = 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]
        t = font.render(str(i) if i < len(GRADIENT_PALETTE) else "inf", True,
                        (0, 0, 0) if lum > 140 else (255, 255, 255))
        strip.blit(t, t.get_rect(center=rect.center))
    return strip


def _flow(items: list[pygame.Surface], max_width: int, margin: int,
          gap: int) -> pygame.Surface:
    """Lay ``items`` out left to right, wrapping at ``max_width``, on a translucent panel."""
    lines: list[list[pygame.Surface]] = [[]]
    x = 0
    for it in items:
        if lines[-1] and x + it.get_width() > max_width:
            lines.append([])
            x = 0
        lines[-1].append(it)
        x += it.get_width() + 2 * gap
    line_h = max(it.get_height() for it in items)
    width = max(sum(it.get_width() for it in ln) + 2 * gap * (len(ln) - 1) for ln in lines)
    panel = pygame.Surface((min(width, max_width) + 2 * margin, line_h * len(lines) + margin),
                           pygame.SRCALPHA)
    panel.fill(PANEL)
    y = margin // 2
    for ln in lines:
        x = margin
        for it in ln:
            panel.blit(it, (x, y + (line_h - it.get_height()) // 2))
            x += it.get_width() + 2 * gap
        y += line_h
    return panel

"""Shapes for worlds: text outlines (matplotlib's TextPath) and black-and-white images
(contourpy) as shapely geometry, holes kept, in their own units with y growing upward.

Every problem with the input is a :class:`ConfigError` naming the option and the value.
"""

from __future__ import annotations

import itertools
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from swarmsim.errors import ConfigError

TEXT_SIZE = 100.0  # glyph em size the outlines are taken at, before scaling
PIXEL_TOLERANCE = 0.75  # traced outlines are simplified to within this many pixels
MIN_PART_SHARE = 0.001  # drop traced specks smaller than this share of the largest shape


def _clean(geom: BaseGeometry) -> BaseGeometry:
    """``geom`` made valid (buffer(0)), with only its polygonal parts."""
    fixed = shapely.make_valid(geom).buffer(0)
    parts = [p for p in shapely.get_parts(fixed) if p.geom_type == "Polygon" and p.area > 0]
    return shapely.union_all(parts) if parts else shapely.Polygon()


def _font(font: str | None):
    """A bold FontProperties for a family name or a font file's path (default DejaVu Sans)."""
    from matplotlib import font_manager

    if font and (font.lower().endswith((".ttf", ".otf", ".ttc")) or Path(font).is_file()):
        if not Path(font).is_file():
            raise ConfigError(f"font file not found: {font!r}", key="--font")
        return font_manager.FontProperties(fname=font)
    prop = font_manager.FontProperties(family=font or "DejaVu Sans", weight="bold")
    try:
        font_manager.findfont(prop, fallback_to_default=False)
    except ValueError:
        raise ConfigError(f"no font family {font!r} on this machine; give a family name "
                          "matplotlib knows or a .ttf file", key="--font") from None
    return prop


def text_shape(text: str, font: str | None = None) -> BaseGeometry:
    """The outline of ``text`` in a bold font (``font``: family name or .ttf path), holes kept
    (the inside of an O, A, B stays free floor), in font units (em size 100), y up.

    Each glyph's rings are ordered by area, largest first; a ring with the orientation of the
    glyph's outer outline adds its area and the other orientation cuts it out, so holes and
    islands inside holes come out right, and overlapping outlines are unioned.
    """
    if not text.strip():
        raise ConfigError(f"no text to draw, got {text!r}", key="--text")
    from matplotlib.textpath import TextPath

    prop = _font(font)
    _check_glyphs(text, prop)
    shapes = []
    x = 0.0
    for ch in text:
        if ch.isspace():
            x += TEXT_SIZE * 0.3
            continue
        path = TextPath((x, 0.0), ch, size=TEXT_SIZE, prop=prop)
        glyph = _glyph(path.to_polygons(closed_only=True))
        if not glyph.is_empty:
            shapes.append(glyph)
            x = glyph.bounds[2] + TEXT_SIZE * 0.08  # a small gap after each glyph
        else:
            x += TEXT_SIZE * 0.3
    shape = _clean(shapely.union_all(shapes)) if shapes else shapely.Polygon()
    if shape.is_empty:
        raise ConfigError(f"the text {text!r} has no shapes in this font", key="--text")
    return shape


def _check_glyphs(text: str, prop) -> None:
    """Refuse characters of ``text`` that the font has no glyph for (it would draw its
    missing-glyph box), naming them and the font file."""
    from matplotlib import font_manager

    path = font_manager.findfont(prop)
    face = font_manager.get_font(path)
    missing = [ch for ch in dict.fromkeys(text)
               if not ch.isspace() and face.get_char_index(ord(ch)) == 0]
    if missing:
        names = ", ".join(f"{ch!r} (U+{ord(ch):04X})" for ch in missing)
        raise ConfigError(f"the font {Path(path).name} ({face.family_name}) has no glyph for "
                          f"{names}; choose another --font or other text", key="--text")


def _glyph(rings: list[np.ndarray]) -> BaseGeometry:
    polys = [(shapely.Polygon(r), shapely.LinearRing(r).is_ccw) for r in rings if len(r) >= 4]
    polys = [(p.buffer(0), ccw) for p, ccw in polys if abs(p.area) > 0]
    if not polys:
        return shapely.Polygon()
    polys.sort(key=lambda pc: -pc[0].area)
    outer_ccw = polys[0][1]
    geom = shapely.Polygon()
    for poly, ccw in polys:
        geom = geom.union(poly) if ccw == outer_ccw else geom.difference(poly)
    return _clean(geom)


def image_shape(path: str | Path, invert: bool = False) -> BaseGeometry:
    """The dark shapes of a black-and-white image (light ones with ``invert``), holes kept,
    traced with contourpy at the half-grey level, in pixels, y up. Transparent pixels count as
    white. Specks under MIN_PART_SHARE of the largest shape are dropped."""
    light = _read_lightness(Path(path))
    mask = light > 0.5 if invert else light < 0.5
    if not mask.any():
        colour = "light" if invert else "dark"
        raise ConfigError(f"{str(path)!r} has no shapes: no {colour} pixels", key="--image")
    if mask.all():
        raise ConfigError(f"{str(path)!r} has no shapes: every pixel is "
                          f"{'light' if invert else 'dark'} (--invert traces the other colour)",
                          key="--image")
    import contourpy

    z = np.pad(mask[::-1].astype(float), 1)  # row 0 at the bottom; closed at the borders
    gen = contourpy.contour_generator(z=z, fill_type="OuterOffset")
    points, offsets = gen.filled(0.5, 2.0)
    polys = []
    for pts, offs in zip(points, offsets, strict=True):
        rings = [pts[a:b] - 1.0 for a, b in itertools.pairwise(offs)]
        if len(rings[0]) >= 4:
            polys.append(shapely.Polygon(rings[0], [r for r in rings[1:] if len(r) >= 4]))
    shape = _clean(shapely.union_all(polys)) if polys else shapely.Polygon()
    parts = list(shapely.get_parts(shape))
    if not parts:
        raise ConfigError(f"{str(path)!r} has no shapes to trace", key="--image")
    biggest = max(p.area for p in parts)
    kept = shapely.union_all([p for p in parts if p.area >= MIN_PART_SHARE * biggest])
    return _clean(kept.simplify(PIXEL_TOLERANCE, preserve_topology=True))


def _read_lightness(path: Path) -> np.ndarray:
    """(rows, cols) lightness in [0, 1] (0 black, 1 white; transparency over white)."""
    import imageio.v3 as iio

    if path.is_dir():
        raise ConfigError(f"{str(path)!r} is a folder; give an image file", key="--image")
    if not path.is_file():
        raise ConfigError(f"image not found: {str(path)!r}", key="--image")
    try:
        with warnings.catch_warnings():  # imageio's deprecated plugins, tried in turn
            warnings.simplefilter("ignore", DeprecationWarning)
            img = np.asarray(iio.imread(path))
    except OSError as exc:
        if exc.strerror:  # permissions, a folder, ...
            raise ConfigError(f"cannot read the image {str(path)!r} ({exc.strerror})",
                              key="--image") from None
        raise ConfigError(f"cannot read the image {str(path)!r}: not an image file imageio "
                          "reads (PNG, JPEG, BMP, ...)", key="--image") from None
    except Exception:  # noqa: BLE001  (imageio's plugins raise many kinds: struct.error, ...)
        raise ConfigError(f"cannot read the image {str(path)!r}: not an image file imageio "
                          "reads (PNG, JPEG, BMP, ...)", key="--image") from None
    if img.ndim == 3 and img.shape[0] > 1 and img.shape[-1] not in (1, 2, 3, 4):
        img = img[0]  # an animation: its first frame
    if img.ndim not in (2, 3) or img.size == 0 or min(img.shape[:2]) < 2:
        raise ConfigError(f"not a 2-D image: {str(path)!r} has shape {img.shape}", key="--image")
    scale = float(np.iinfo(img.dtype).max) if img.dtype.kind in "ui" else 1.0
    img = img.astype(float) / scale
    if img.ndim == 2:
        return img
    channels = img.shape[2]
    alpha = img[..., -1] if channels in (2, 4) else np.ones(img.shape[:2])
    colour = img[..., :3] if channels >= 3 else img[..., :1]
    value = colour @ np.array([0.299, 0.587, 0.114]) if colour.shape[2] == 3 else colour[..., 0]
    return alpha * value + (1.0 - alpha)

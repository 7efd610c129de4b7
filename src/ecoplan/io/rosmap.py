"""Read ROS ``map_server`` maps (map YAML + PGM/PNG image) and terrain label images.

Semantics follow Nav2 ``nav2_map_server/src/map_io.cpp`` (``loadMapYaml`` and
``loadMapFromFile``), checked against its source:

* YAML keys: ``image`` (relative to the YAML file), ``resolution`` [m/cell], ``origin``
  ``[x, y, yaw]`` (exactly 3 numbers: the map-frame pose of the **lower-left** pixel),
  ``occupied_thresh``, ``free_thresh``, ``negate`` (0/1 or bool), ``mode`` (``trinary``
  default, ``scale``, ``raw``).  Nav2 requires ``negate``; here it defaults to 0.  A
  non-zero ``yaw`` is rejected (ecoplan grids are axis-aligned).
* Per pixel, ``shade`` is the mean of the colour channels scaled to 0..1 (in ``trinary``
  mode the alpha channel, when the image has one, is averaged in as a fourth channel),
  and ``occ = shade`` if ``negate`` else ``1 - shade``.
* ``trinary``: ``occ > occupied_thresh`` → 100, ``occ < free_thresh`` → 0, else -1
  (unknown).  ``scale``: a pixel that is not fully opaque → -1; then the same two
  thresholds, and in between ``rint((occ - free) / (occupied - free) * 100)``.
  ``raw``: ``round(shade * 255)`` if in 0..100, else -1 (``negate`` is ignored).
* Image row ``y`` (top row 0) becomes grid row ``height - 1 - y``: the image's bottom row
  is the grid's row 0, at ``origin``.

Images are decoded with Pillow (PGM P2/P5 with comment lines, PNG, 8 or 16 bit).
Every error is an :class:`ecoplan.errors.InputError` whose one-line message names the
file and the field.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import yaml
from PIL import Image, UnidentifiedImageError

from ecoplan._typing import FloatArray
from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap, UnknownPolicy

__all__ = [
    "MapError",
    "MapMode",
    "RosMapMeta",
    "load_ros_map",
    "load_terrain_layer",
    "occupancy_from_image",
    "read_map_yaml",
]

MapMode = Literal["trinary", "scale", "raw"]


class MapError(InputError):
    """A map YAML, map image or terrain image is invalid (the message names file and field)."""


@dataclass(frozen=True, slots=True)
class RosMapMeta:
    """The fields of a ``map_server`` map YAML.

    Attributes
    ----------
    image : Path
        Image file (resolved against the YAML's folder).
    resolution_m : float
        Cell size [m/cell].
    origin_xy_m : tuple of float
        Map-frame position of the lower-left pixel's corner [m].
    occupied_thresh, free_thresh : float
        Thresholds on ``occ`` in 0..1 (module doc).
    negate : bool
        Whether white means occupied.
    mode : {"trinary", "scale", "raw"}
        Pixel interpretation.
    """

    image: Path
    resolution_m: float
    origin_xy_m: tuple[float, float]
    occupied_thresh: float
    free_thresh: float
    negate: bool
    mode: MapMode


def _number(src: Path, doc: Mapping[str, Any], key: str) -> float:
    if key not in doc:
        raise MapError(f"{src}: missing field '{key}'")
    val = doc[key]
    if isinstance(val, bool) or not isinstance(val, int | float) or not math.isfinite(val):
        raise MapError(f"{src}: field '{key}' must be a finite number, got {val!r}")
    return float(val)


def read_map_yaml(path: str | Path) -> RosMapMeta:
    """Parse and check a ``map_server`` map YAML (module doc).

    Raises
    ------
    MapError
        Unreadable file, missing or invalid field; the message names the file and field.
    """
    src = Path(path)
    try:
        doc = yaml.safe_load(src.read_text(encoding="utf-8"))
    except OSError as exc:
        raise MapError(f"{src}: cannot read map YAML ({exc.strerror})") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise MapError(f"{src}: invalid YAML{where}") from None
    if not isinstance(doc, dict):
        raise MapError(f"{src}: a map YAML must be a mapping of fields")
    image = doc.get("image")
    if not isinstance(image, str) or not image:
        raise MapError(f"{src}: field 'image' must name the map image, got {image!r}")
    res = _number(src, doc, "resolution")
    if res <= 0.0:
        raise MapError(f"{src}: field 'resolution' must be > 0 m/cell, got {res:g}")
    origin = doc.get("origin")
    if (
        not isinstance(origin, list)
        or len(origin) != 3
        or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in origin)
        or not all(math.isfinite(v) for v in origin)
    ):
        raise MapError(f"{src}: field 'origin' must be [x, y, yaw] (3 numbers), got {origin!r}")
    if origin[2] != 0:
        raise MapError(
            f"{src}: field 'origin' has yaw {origin[2]!r}; only axis-aligned maps (yaw 0) "
            "are supported"
        )
    occ_th = _number(src, doc, "occupied_thresh")
    free_th = _number(src, doc, "free_thresh")
    if not (0.0 <= free_th < occ_th <= 1.0):
        raise MapError(
            f"{src}: fields 'free_thresh' ({free_th:g}) and 'occupied_thresh' ({occ_th:g}) "
            "must satisfy 0 <= free_thresh < occupied_thresh <= 1"
        )
    negate = doc.get("negate", 0)
    if negate not in (0, 1):  # True/False compare equal to 1/0
        raise MapError(f"{src}: field 'negate' must be 0 or 1, got {negate!r}")
    mode = doc.get("mode", "trinary")
    if mode not in ("trinary", "scale", "raw"):
        raise MapError(f"{src}: field 'mode' must be trinary, scale or raw, got {mode!r}")
    img = Path(image)
    if not img.is_absolute():
        img = src.parent / img
    return RosMapMeta(
        image=img,
        resolution_m=res,
        origin_xy_m=(float(origin[0]), float(origin[1])),
        occupied_thresh=occ_th,
        free_thresh=free_th,
        negate=bool(negate),
        mode=mode,
    )


def _open_image(path: Path, what: str) -> Image.Image:
    if not path.is_file():
        raise MapError(f"{path}: {what} not found")
    try:
        with Image.open(path) as opened:
            opened.load()
            img = opened.copy()
    except FileNotFoundError:
        raise MapError(f"{path}: {what} not found") from None
    except (UnidentifiedImageError, OSError, ValueError) as exc:
        raise MapError(f"{path}: cannot decode {what} ({type(exc).__name__})") from None
    return img


def _channels(img: Image.Image) -> tuple[FloatArray, FloatArray | None]:
    """Colour channels scaled to 0..1, shape (h, w, c), and alpha (0..1) or None."""
    if img.mode in ("I;16", "I;16B", "I;16L", "I"):
        arr = np.asarray(img, dtype=np.float64)
        top = 65535.0 if img.mode.startswith("I;16") or arr.max(initial=0) > 255 else 255.0
        return arr[:, :, None] / top, None
    has_alpha = img.mode in ("RGBA", "LA", "PA") or (img.mode == "P" and "transparency" in img.info)
    if img.mode in ("L", "1"):
        return np.asarray(img.convert("L"), dtype=np.float64)[:, :, None] / 255.0, None
    if img.mode == "LA" or (img.mode == "P" and has_alpha and _is_grey_palette(img)):
        la = np.asarray(img.convert("LA"), dtype=np.float64) / 255.0
        return la[:, :, :1], la[:, :, 1]
    rgba = np.asarray(img.convert("RGBA"), dtype=np.float64) / 255.0
    return rgba[:, :, :3], (rgba[:, :, 3] if has_alpha else None)


def _is_grey_palette(img: Image.Image) -> bool:
    pal = np.asarray(img.convert("RGB"))
    return bool(np.all(pal[:, :, 0] == pal[:, :, 1]) and np.all(pal[:, :, 1] == pal[:, :, 2]))


def occupancy_from_image(
    channels: FloatArray,
    alpha: FloatArray | None,
    *,
    mode: MapMode = "trinary",
    negate: bool = False,
    occupied_thresh: float = 0.65,
    free_thresh: float = 0.25,
) -> npt.NDArray[np.int8]:
    """``nav_msgs/OccupancyGrid`` values from image channels (Nav2 ``loadMapFromFile``).

    Parameters
    ----------
    channels : ndarray, shape (h, w, c)
        Colour channels scaled to 0..1, image row 0 at the top.
    alpha : ndarray, shape (h, w), or None
        Opacity in 0..1 (1 = opaque), None for images without alpha.
    mode, negate, occupied_thresh, free_thresh
        As in the map YAML (module doc).

    Returns
    -------
    ndarray of int8, shape (h, w)
        Values 0..100 or -1, **grid row 0 = image bottom row**.
    """
    chans = np.asarray(channels, dtype=np.float64)
    if mode == "trinary" and alpha is not None:
        chans = np.concatenate([chans, np.asarray(alpha)[:, :, None]], axis=2)
    shade = chans.mean(axis=2)
    occ = shade if negate else 1.0 - shade
    out = np.full(shade.shape, -1, dtype=np.int8)
    if mode == "raw":
        val = np.round(shade * 255.0)
        ok = (val >= 0) & (val <= 100)
        out[ok] = val[ok].astype(np.int8)
    else:
        out[occ > occupied_thresh] = 100
        out[occ < free_thresh] = 0
        if mode == "scale":
            mid = (occ >= free_thresh) & (occ <= occupied_thresh)
            scaled = np.rint((occ - free_thresh) / (occupied_thresh - free_thresh) * 100.0)
            out[mid] = scaled[mid].astype(np.int8)
            if alpha is not None:
                out[np.asarray(alpha) < 1.0] = -1
    return np.ascontiguousarray(out[::-1])


def load_terrain_layer(
    path: str | Path,
    legend: Mapping[int, str | None],
    shape: tuple[int, int],
    *,
    default: str | None = None,
) -> tuple[npt.NDArray[np.uint8], tuple[str | None, ...]]:
    """Terrain labels from a label image on the map's grid.

    Parameters
    ----------
    path : str or Path
        Single-channel image (PGM/PNG, 8 bit, or a palette PNG: its indices are the values).
    legend : mapping of int to str
        Pixel value → terrain preset name.  Every value present must be in the legend.
    shape : tuple of int
        ``(ny, nx)`` of the occupancy grid (the image must have the same size).
    default : str or None
        Terrain of label 0 (used by nothing in the image unless the legend maps to it).

    Returns
    -------
    labels : ndarray of uint8, shape (ny, nx)
        Label per cell, grid row 0 = image bottom row.
    names : tuple
        Terrain name per label (label 0 is ``default``).

    Raises
    ------
    MapError
        Wrong size, a multi-channel image, or pixel values missing from the legend.
    """
    src = Path(path)
    img = _open_image(src, "terrain image")
    if img.mode not in ("L", "P", "1", "I;16", "I"):
        raise MapError(
            f"{src}: a terrain image must have one channel (grey or palette), got mode {img.mode}"
        )
    values = np.asarray(img, dtype=np.int64)
    if values.shape != tuple(shape):
        raise MapError(
            f"{src}: terrain image is {values.shape[1]} x {values.shape[0]} pixels but the map "
            f"is {shape[1]} x {shape[0]}"
        )
    names: list[str | None] = [default]
    lut: dict[int, int] = {}
    for key, terr in legend.items():
        if isinstance(key, bool) or not isinstance(key, int):
            raise MapError(f"{src}: legend key {key!r} must be a pixel value (integer)")
        if terr is not None and not isinstance(terr, str):
            raise MapError(f"{src}: legend value for pixel {key} must be a terrain name")
        if terr not in names:
            names.append(terr)
        lut[int(key)] = names.index(terr)
    present = np.unique(values)
    missing = [int(v) for v in present if int(v) not in lut]
    if missing:
        raise MapError(
            f"{src}: pixel values {missing[:5]} are not in the terrain legend "
            f"(legend keys: {sorted(lut)})"
        )
    if len(names) > 255:
        raise MapError(f"{src}: at most 255 terrains per map, got {len(names)}")
    table = np.zeros(int(present.max()) + 1, dtype=np.uint8)
    for key, idx in lut.items():
        if key < len(table):
            table[key] = idx
    labels = table[values][::-1]
    return np.ascontiguousarray(labels), tuple(names)


def load_ros_map(
    path: str | Path,
    *,
    inflation_m: float = 0.0,
    unknown: UnknownPolicy = "obstacle",
    terrain_image: str | Path | None = None,
    terrain_legend: Mapping[int, str | None] | None = None,
    default_terrain: str | None = None,
) -> GridMap:
    """Read a ``map_server`` map (YAML + image) into an inflated :class:`GridMap`.

    Parameters
    ----------
    path : str or Path
        The map YAML.
    inflation_m : float
        Robot footprint radius [m] (see :func:`ecoplan.geometry.maps.inflate`).
    unknown : {"obstacle", "free"}
        Policy for unknown cells (default: obstacle).
    terrain_image : str or Path, optional
        Label image on the same grid (relative paths: against the YAML's folder).
    terrain_legend : mapping of int to str, optional
        Pixel value → terrain name; required with ``terrain_image``.
    default_terrain : str or None
        Terrain where no layer is given (``None``: the vehicle's default).

    Returns
    -------
    GridMap

    Raises
    ------
    MapError
        One line naming the file and the field.
    """
    meta = read_map_yaml(path)
    img = _open_image(meta.image, "map image")
    chans, alpha = _channels(img)
    occ = occupancy_from_image(
        chans,
        alpha,
        mode=meta.mode,
        negate=meta.negate,
        occupied_thresh=meta.occupied_thresh,
        free_thresh=meta.free_thresh,
    )
    terrain = None
    names: tuple[str | None, ...] = (default_terrain,)
    if terrain_image is not None:
        if terrain_legend is None:
            raise MapError(f"{terrain_image}: a terrain image needs a legend (value: terrain)")
        timg = Path(terrain_image)
        if not timg.is_absolute():
            timg = Path(path).parent / timg
        terrain, names = load_terrain_layer(
            timg, terrain_legend, occ.shape, default=default_terrain
        )
    try:
        return GridMap(
            occ,
            resolution_m=meta.resolution_m,
            origin_xy_m=meta.origin_xy_m,
            inflation_m=inflation_m,
            terrain=terrain,
            terrain_names=names,
            unknown=unknown,
        )
    except InputError as exc:
        raise MapError(f"{path}: {exc}") from None

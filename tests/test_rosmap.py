"""ROS map_server maps and terrain layers (ecoplan.io.rosmap, ecoplan.geometry.maps).

Expected grids are computed here from the bytes the tests write (a hand-made PGM is
parsed by hand, independently of Pillow) and from Nav2's documented rules
(nav2_map_server map_io.cpp loadMapFromFile): occ = 1 - shade (negate: shade),
trinary: occ > occupied_thresh -> 100, occ < free_thresh -> 0, else -1; image row y is
grid row height - 1 - y.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap, inflate, rasterise_world
from ecoplan.geometry.world import PointInObstacleError, World, rectangle
from ecoplan.io.rosmap import MapError, load_ros_map, load_terrain_layer

W, H = 40, 30


def _pixels() -> np.ndarray:
    """A SLAM-looking map: free 254, walls 0, unknown 205 outside, a grey smudge."""
    img = np.full((H, W), 254, dtype=np.uint8)
    img[:, :3] = 205  # unknown strip on the left (never observed)
    img[0, :] = 0  # top wall
    img[10:20, 20] = 0  # a thin wall
    img[25, 30:35] = 120  # grey: occ = 1 - 120/255 = 0.53 -> unknown in trinary
    return img


def _write_pgm(path: Path, img: np.ndarray) -> None:
    header = (
        b"P5\n# CREATOR: map_saver.cpp 0.100 m/pix\n"
        + f"{img.shape[1]} {img.shape[0]}\n".encode()
        + b"# a comment between fields\n255\n"
    )
    path.write_bytes(header + img.tobytes())


def _parse_pgm_by_hand(path: Path) -> np.ndarray:
    """Independent P5 reader: tokens separated by whitespace, '#' to end of line."""
    data = path.read_bytes()
    tokens: list[bytes] = []
    i = 0
    while len(tokens) < 4:
        c = data[i : i + 1]
        if c == b"#":
            i = data.index(b"\n", i) + 1
        elif c.isspace():
            i += 1
        else:
            j = i
            while not data[j : j + 1].isspace():
                j += 1
            tokens.append(data[i:j])
            i = j
    assert tokens[0] == b"P5"
    w, h, maxval = int(tokens[1]), int(tokens[2]), int(tokens[3])
    assert maxval == 255
    raster = data[i + 1 : i + 1 + w * h]  # one whitespace byte after maxval
    return np.frombuffer(raster, dtype=np.uint8).reshape(h, w)


def _expected(img: np.ndarray, occ_th: float, free_th: float, negate: bool) -> np.ndarray:
    out = np.empty(img.shape, dtype=np.int8)
    for y in range(img.shape[0]):
        for x in range(img.shape[1]):
            shade = img[y, x] / 255.0
            occ = shade if negate else 1.0 - shade
            val = 100 if occ > occ_th else (0 if occ < free_th else -1)
            out[img.shape[0] - 1 - y, x] = val
    return out


def _yaml(path: Path, image: str, **over: object) -> Path:
    fields: dict[str, object] = {
        "image": image,
        "mode": "trinary",
        "resolution": 0.1,
        "origin": [-1.0, -2.0, 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    fields.update(over)
    lines = [f"{k}: {v}" for k, v in fields.items() if v is not None]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("negate", [False, True])
def test_trinary_pgm_matches_independent_read(tmp_path: Path, negate: bool) -> None:
    _write_pgm(tmp_path / "site.pgm", _pixels())
    y = _yaml(tmp_path / "site.yaml", "site.pgm", negate=int(negate))
    grid = load_ros_map(y)
    raw = _parse_pgm_by_hand(tmp_path / "site.pgm")
    np.testing.assert_array_equal(raw, _pixels())
    expected = _expected(raw, 0.65, 0.196, negate)
    np.testing.assert_array_equal(grid.occupancy, expected)
    assert grid.resolution_m == 0.1
    assert grid.origin_xy_m == (-1.0, -2.0)
    if not negate:
        # the top image row is a wall: it is the last grid row (highest y)
        assert (grid.occupancy[-1] == 100).all()
        assert (grid.occupancy[:-1, :3] == -1).all()


def test_unknown_policy_and_lookup(tmp_path: Path) -> None:
    _write_pgm(tmp_path / "site.pgm", _pixels())
    y = _yaml(tmp_path / "site.yaml", "site.pgm")
    strict = load_ros_map(y)
    lax = load_ros_map(y, unknown="free")
    # cell (row 10, col 1) is in the unknown strip; its centre in the map frame:
    x, yy = -1.0 + 1.5 * 0.1, -2.0 + 10.5 * 0.1
    assert not bool(strict.is_free(x, yy))
    assert bool(lax.is_free(x, yy))
    with pytest.raises(PointInObstacleError, match="unknown cell"):
        strict.check_point((x, yy), "start")


def test_ascii_pgm_and_png_scale_with_alpha(tmp_path: Path) -> None:
    # P2 (ASCII) with comments: Pillow decodes it, values checked against the text we wrote
    vals = np.array([[0, 128, 255], [205, 60, 250]], dtype=np.uint8)
    text = "P2\n# ascii map\n3 2\n255\n" + "\n".join(" ".join(map(str, r)) for r in vals) + "\n"
    (tmp_path / "a.pgm").write_text(text)
    g = load_ros_map(_yaml(tmp_path / "a.yaml", "a.pgm"))
    np.testing.assert_array_equal(g.occupancy, _expected(vals, 0.65, 0.196, False))
    # scale mode, PNG with alpha: transparent -> -1, in between -> linear 0..100
    rgba = np.zeros((1, 3, 4), dtype=np.uint8)
    rgba[0, :, :3] = [[255, 255, 255], [100, 100, 100], [100, 100, 100]]
    rgba[0, :, 3] = [255, 255, 128]
    Image.fromarray(rgba, "RGBA").save(tmp_path / "s.png")
    gs = load_ros_map(_yaml(tmp_path / "s.yaml", "s.png", mode="scale"), unknown="free")
    occ_mid = 1.0 - 100 / 255.0  # 0.608, between free 0.196 and occupied 0.65
    expect_mid = round((occ_mid - 0.196) / (0.65 - 0.196) * 100.0)
    np.testing.assert_array_equal(gs.occupancy[0], [0, expect_mid, -1])


def test_raw_mode(tmp_path: Path) -> None:
    vals = np.array([[0, 50, 100, 101, 255]], dtype=np.uint8)
    Image.fromarray(vals, "L").save(tmp_path / "r.png")
    g = load_ros_map(_yaml(tmp_path / "r.yaml", "r.png", mode="raw"), unknown="free")
    np.testing.assert_array_equal(g.occupancy[0], [0, 50, 100, -1, -1])


@pytest.mark.parametrize(
    ("over", "needle"),
    [
        ({"resolution": None}, "missing field 'resolution'"),
        ({"resolution": -1}, "'resolution' must be > 0"),
        ({"origin": "[0, 0]"}, "'origin' must be [x, y, yaw]"),
        ({"origin": "[0, 0, 0.5]"}, "yaw 0.5"),
        ({"free_thresh": 0.9}, "'free_thresh'"),
        ({"negate": 2}, "'negate' must be 0 or 1"),
        ({"mode": "fancy"}, "'mode' must be trinary"),
        ({"image_name": "nothere.pgm"}, "map image not found"),
    ],
)
def test_yaml_errors_name_file_and_field(tmp_path: Path, over: dict, needle: str) -> None:
    _write_pgm(tmp_path / "site.pgm", _pixels())
    image = str(over.pop("image_name", "site.pgm"))
    y = _yaml(tmp_path / "bad.yaml", image, **over)
    with pytest.raises(MapError) as err:
        load_ros_map(y)
    msg = str(err.value)
    assert needle in msg
    assert "\n" not in msg
    assert "bad.yaml" in msg or "nothere.pgm" in msg


def test_garbage_image_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "x.pgm").write_bytes(b"P5\n3 2\n255\n\x00")  # truncated raster
    with pytest.raises(InputError, match=r"x\.pgm: cannot decode map image"):
        load_ros_map(_yaml(tmp_path / "x.yaml", "x.pgm"))


def test_inflation_matches_brute_force() -> None:
    rng = np.random.default_rng(3)
    obs = rng.random((25, 31)) < 0.03
    res, radius = 0.1, 0.25
    got = inflate(obs, radius, res)
    # independent: min distance from each cell centre to obstacle centres and to the
    # outside ring (the border counts as obstacle), in cells
    ny, nx = obs.shape
    rr, cc = np.mgrid[-1 : ny + 1, -1 : nx + 1]
    ring = (rr < 0) | (rr >= ny) | (cc < 0) | (cc >= nx)
    src = np.zeros(rr.shape, dtype=bool)
    src[1:-1, 1:-1] = obs
    src |= ring
    sr, sc = rr[src], cc[src]
    gr, gc = np.mgrid[0:ny, 0:nx]
    d = np.sqrt((gr[..., None] - sr) ** 2 + (gc[..., None] - sc) ** 2).min(axis=-1)
    expected = d < radius / res + math.sqrt(0.5)
    np.testing.assert_array_equal(got, expected)


def test_terrain_layer_legend(tmp_path: Path) -> None:
    labels = np.zeros((H, W), dtype=np.uint8)
    labels[:, 10:20] = 1
    labels[:5, :] = 2
    Image.fromarray(labels, "L").save(tmp_path / "t.png")
    _write_pgm(tmp_path / "site.pgm", _pixels())
    g = load_ros_map(
        _yaml(tmp_path / "site.yaml", "site.pgm"),
        terrain_image="t.png",
        terrain_legend={0: "grass", 1: "asphalt", 2: "gravel"},
        default_terrain="grass",
    )
    assert g.terrain_names == ("grass", "asphalt", "gravel")
    # image top rows (label 2) are the highest y: grid rows H-5..H-1
    assert g.terrain_at([g.cell_centre(H - 1, 0)])[0] == "gravel"
    assert g.terrain_at([g.cell_centre(0, 15)])[0] == "asphalt"
    with pytest.raises(MapError, match=r"pixel values \[2\] are not in the terrain legend"):
        load_terrain_layer(tmp_path / "t.png", {0: "grass", 1: "asphalt"}, (H, W))
    with pytest.raises(MapError, match="40 x 30 pixels but the map is 4 x 3"):
        load_terrain_layer(tmp_path / "t.png", {0: "a", 1: "b", 2: "c"}, (3, 4))


def test_rasterised_world_agrees_with_polygons() -> None:
    w = World(
        rectangle(0, 0, 12, 8),
        [rectangle(4, 2, 6, 5)],
        inflation_m=0.3,
        regions=[(rectangle(0, 0, 3, 8), "asphalt")],
        default_terrain="marble",
    )
    g = rasterise_world(w, 0.1)
    assert g.shape == (80, 120)
    # the obstacle covers cells x in [4, 6), y in [2, 5) (20 x 30 cells), plus at most
    # a one-cell outline
    inner = g.obstacle[21:49, 41:59]
    assert inner.all()
    assert g.obstacle[15:60, 30:75].sum() <= 22 * 32
    # points further than one cell + inflation from every boundary agree with the world
    rng = np.random.default_rng(0)
    pts = rng.uniform([0, 0], [12, 8], size=(400, 2))
    ox = np.maximum(np.maximum(4 - pts[:, 0], pts[:, 0] - 6), 0)
    oy = np.maximum(np.maximum(2 - pts[:, 1], pts[:, 1] - 5), 0)
    d_obs = np.hypot(ox, oy)
    d_border = np.minimum.reduce([pts[:, 0], 12 - pts[:, 0], pts[:, 1], 8 - pts[:, 1]])
    clear = (np.abs(d_obs - 0.3) > 0.25) & (np.abs(d_border - 0.3) > 0.25)
    np.testing.assert_array_equal(
        g.is_free(pts[clear, 0], pts[clear, 1]), w.is_free(pts[clear, 0], pts[clear, 1])
    )
    assert g.terrain_at([(1.0, 1.0), (8.0, 1.0)]) == ["asphalt", "marble"]


@settings(max_examples=40, deadline=None)
@given(
    x0=st.floats(0.1, 11.9),
    y0=st.floats(0.1, 7.9),
    x1=st.floats(0.1, 11.9),
    y1=st.floats(0.1, 7.9),
)
def test_split_by_terrain_pieces_tile_the_segment(
    x0: float, y0: float, x1: float, y1: float
) -> None:
    occ = np.zeros((80, 120), dtype=np.int8)
    labels = np.zeros((80, 120), dtype=np.uint8)
    labels[:, 30:60] = 1
    labels[40:, :] = 2
    g = GridMap(occ, 0.1, terrain=labels, terrain_names=("a", "b", "c"))
    pieces = g.split_by_terrain((x0, y0), (x1, y1))
    total = math.hypot(x1 - x0, y1 - y0)
    assert sum(p.length_m for p in pieces) == pytest.approx(total, abs=1e-9)
    assert all(pieces[i].terrain != pieces[i + 1].terrain for i in range(len(pieces) - 1))
    for p in pieces:
        if p.length_m > 0.1:
            mid = ((p.start[0] + p.end[0]) / 2, (p.start[1] + p.end[1]) / 2)
            assert g.terrain_at([mid])[0] == p.terrain


def test_gridmap_rejects_bad_input() -> None:
    with pytest.raises(InputError, match=r"occupancy values must be in -1\.\.100"):
        GridMap(np.full((3, 3), 120, dtype=np.int16), 0.1)
    with pytest.raises(InputError, match="no free cell is left"):
        GridMap(np.zeros((3, 3), dtype=np.int8), 0.1, inflation_m=1.0)
    with pytest.raises(InputError, match=r"terrain labels must be in 0\.\.0"):
        GridMap(np.zeros((3, 3), dtype=np.int8), 0.1, terrain=np.ones((3, 3), dtype=np.uint8))


def _segment_free_by_loop(g: GridMap, a: np.ndarray, b: np.ndarray) -> bool:
    """Independent per-segment check: samples a quarter cell apart, cell by cell."""
    n = max(math.ceil(math.hypot(*(b - a)) / (g.resolution_m / 4.0)), 1)
    for t in np.linspace(0.0, 1.0, n + 1):
        x, y = a + t * (b - a)
        col = math.floor((x - g.origin_xy_m[0]) / g.resolution_m)
        row = math.floor((y - g.origin_xy_m[1]) / g.resolution_m)
        ny, nx = g.shape
        if not (0 <= row < ny and 0 <= col < nx) or g.blocked[row, col]:
            return False
    return True


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n_seg=st.integers(1, 12),
)
def test_vectorised_segment_checks_match_a_loop(seed: int, n_seg: int) -> None:
    rng = np.random.default_rng(seed)
    occ = np.where(rng.random((30, 40)) < 0.08, 100, 0).astype(np.int8)
    g = GridMap(occ, 0.1, inflation_m=0.0, origin_xy_m=(-0.3, 0.2))
    a = rng.uniform([-0.5, 0.0], [4.2, 3.4], size=(n_seg, 2))
    b = rng.uniform([-0.5, 0.0], [4.2, 3.4], size=(n_seg, 2))
    want = [_segment_free_by_loop(g, p, q) for p, q in zip(a, b, strict=True)]
    assert g.segments_free(a, b).tolist() == want
    assert [g.segment_free(p, q) for p, q in zip(a, b, strict=True)] == want
    poly = np.vstack([a[:1], b])
    want_poly = all(_segment_free_by_loop(g, p, q) for p, q in itertools.pairwise(poly))
    assert g.polyline_free(poly) == want_poly
    lines = np.stack([poly, poly[::-1], poly + 0.05])
    want_lines = [
        all(_segment_free_by_loop(g, p, q) for p, q in itertools.pairwise(ln)) for ln in lines
    ]
    assert g.polylines_free(lines).tolist() == want_lines


@given(x=st.floats(-3.0, 3.0, allow_nan=False), y=st.floats(-3.0, 3.0, allow_nan=False))
@settings(max_examples=60, deadline=None)
def test_terrain_outside_the_grid_reads_the_nearest_border_cell(x: float, y: float) -> None:
    """A 3 x 4 grid at 0.5 m from (-1, -0.5): the label of the cell nearest the point, by hand."""
    labels = np.arange(12, dtype=np.uint8).reshape(3, 4)
    g = GridMap(
        np.zeros((3, 4), dtype=np.int8),
        0.5,
        origin_xy_m=(-1.0, -0.5),
        terrain=labels,
        terrain_names=tuple(f"t{i}" for i in range(12)),
    )
    col = min(max(math.floor((x + 1.0) / 0.5), 0), 3)
    row = min(max(math.floor((y + 0.5) / 0.5), 0), 2)
    assert int(g.terrain_id_at([[x, y]])[0]) == 4 * row + col
    assert bool(g.is_free(x, y)) == (-1.0 <= x < 1.0 and -0.5 <= y < 1.0)

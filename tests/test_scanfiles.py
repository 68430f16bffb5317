"""Scanner files written by their own libraries (plyfile, pypcd4, laspy with lazrs, pye57), read by crustview.

Each carries colours, intensity and (PLY, PCD) normals of a torus sample; the
normals are the torus's true ones, so the angle to AN_s is small, and the
report and the command line say so.
"""

import json
import subprocess
import sys
import time

import numpy as np
import pytest

from crustview.attributes import normal_angles
from crustview.core.errors import InputError
from crustview.io import read_attributes, read_points

N = 1500


@pytest.fixture(scope="module")
def torus():
    """A torus sample with its true unit normals, colours in 0..255 and an intensity."""
    from crustview.core.samples.manifolds import get_manifold

    pts = get_manifold("torus").sample(N, seed=0).points
    r_xy = np.hypot(pts[:, 0], pts[:, 1])
    radius = 0.5 * (r_xy.max() + r_xy.min())  # of the core circle
    centre = np.column_stack([pts[:, 0] / r_xy, pts[:, 1] / r_xy, np.zeros(len(pts))]) * radius
    normals = pts - centre
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    colors = np.column_stack([(pts[:, 2] > 0) * 255, np.full(N, 40), (pts[:, 2] <= 0) * 255]).astype(np.uint8)
    intensity = (np.arange(N) % 100).astype(np.float32)
    return pts, normals, colors, intensity


def _write_ply(path, pts, normals, colors, intensity, text=False):
    from plyfile import PlyData, PlyElement

    dt = [(c, "f4") for c in ("x", "y", "z", "nx", "ny", "nz")] + [(c, "u1") for c in ("red", "green", "blue")]
    dt.append(("intensity", "f4"))
    vert = np.empty(len(pts), dtype=dt)
    for i, c in enumerate("xyz"):
        vert[c] = pts[:, i]
    for i, c in enumerate(("nx", "ny", "nz")):
        vert[c] = normals[:, i]
    for i, c in enumerate(("red", "green", "blue")):
        vert[c] = colors[:, i]
    vert["intensity"] = intensity
    PlyData([PlyElement.describe(vert, "vertex")], text=text).write(str(path))


@pytest.mark.parametrize("text", [False, True])
def test_a_plyfile_ply_gives_points_normals_colours_and_intensity(tmp_path, torus, text):
    pts, normals, colors, intensity = torus
    path = tmp_path / "scan.ply"
    _write_ply(path, pts, normals, colors, intensity, text=text)
    attrs: dict = {}
    got = read_points(path, None, attrs)
    assert np.allclose(got, pts, atol=1e-5)
    assert set(attrs) == {"colors", "intensity", "normals"}
    assert np.allclose(attrs["colors"] * 255, colors) and np.allclose(attrs["intensity"], intensity)
    assert np.allclose(attrs["normals"], normals, atol=1e-6)


def test_a_binary_ply_of_a_million_points_reads_in_about_a_second(tmp_path):
    rng = np.random.default_rng(0)
    n = 1_000_000
    pts = rng.normal(size=(n, 3))
    path = tmp_path / "big.ply"
    _write_ply(path, pts, pts / np.linalg.norm(pts, axis=1, keepdims=True), np.zeros((n, 3), np.uint8), np.ones(n))
    start = time.perf_counter()
    attrs: dict = {}
    got = read_points(path, None, attrs)
    seconds = time.perf_counter() - start
    assert got.shape == (n, 3) and attrs["normals"].shape == (n, 3)
    assert seconds < 3.0, f"{seconds:.2f} s"  # about 0.3 s here; the bound leaves room for a busy machine


def test_a_pypcd4_pcd_gives_points_normals_and_colours(tmp_path, torus):
    import pypcd4

    pts, normals, colors, intensity = torus
    rgb = pypcd4.PointCloud.encode_rgb(colors)
    fields = ("x", "y", "z", "normal_x", "normal_y", "normal_z", "intensity", "rgb")
    types = (np.float32,) * 7 + (np.float32,)
    data = np.column_stack([pts, normals, intensity, rgb])
    pc = pypcd4.PointCloud.from_points(data, fields, types)
    path = tmp_path / "scan.pcd"
    pc.save(path)
    attrs: dict = {}
    got = read_points(path, None, attrs)
    assert np.allclose(got, pts, atol=1e-5)
    assert np.allclose(attrs["normals"], normals, atol=1e-6) and np.allclose(attrs["intensity"], intensity)
    assert np.allclose(attrs["colors"] * 255, colors)


@pytest.mark.parametrize("suffix", [".las", ".laz"])
def test_a_laspy_las_and_laz_give_points_colours_and_intensity(tmp_path, torus, suffix):
    import laspy

    pts, _, colors, intensity = torus
    header = laspy.LasHeader(point_format=3, version="1.2")
    header.scales = np.array([1e-4, 1e-4, 1e-4])
    header.offsets = np.zeros(3)
    las = laspy.LasData(header)
    las.x, las.y, las.z = pts[:, 0], pts[:, 1], pts[:, 2]
    las.red, las.green, las.blue = (colors.astype(np.uint16) * 257).T
    las.intensity = intensity.astype(np.uint16)
    path = tmp_path / f"scan{suffix}"
    las.write(path)
    assert path.read_bytes()[:4] == b"LASF"
    if suffix == ".laz":  # compressed by lazrs: point data well under the LAS record size (34 bytes per point)
        assert path.stat().st_size < 34 * N
    attrs: dict = {}
    got = read_points(path, None, attrs)
    assert np.allclose(got, pts, atol=1e-4)
    assert np.allclose(attrs["colors"] * 255, colors) and np.allclose(attrs["intensity"], intensity)
    assert read_attributes(path).keys() == {"colors", "intensity"}


def test_a_pye57_e57_gives_points_colours_and_intensity(tmp_path, torus):
    import pye57

    pts, _, colors, intensity = torus
    path = tmp_path / "scan.e57"
    e57 = pye57.E57(str(path), mode="w")
    e57.write_scan_raw(
        {
            "cartesianX": pts[:, 0],
            "cartesianY": pts[:, 1],
            "cartesianZ": pts[:, 2],
            "intensity": intensity.astype(np.float64) / 100.0,
            "colorRed": colors[:, 0],
            "colorGreen": colors[:, 1],
            "colorBlue": colors[:, 2],
        }
    )
    e57.close()
    attrs: dict = {}
    got = read_points(path, None, attrs)
    assert np.allclose(got, pts, atol=1e-6)
    assert np.allclose(attrs["colors"] * 255, colors) and np.allclose(attrs["intensity"], intensity / 100.0)


def test_normal_angles_are_small_for_true_normals_and_the_report_has_them(tmp_path, torus):
    from crustview.core import reconstruct

    pts, normals, colors, intensity = torus
    rec = reconstruct(pts, 2)
    ang = normal_angles(rec, normals)
    assert ang.shape == (N,) and np.isfinite(ang).all() and np.median(ang) < 5 and ang.max() < 30
    turned = np.cross(normals, [0.0, 0.0, 1.0])  # a tangent direction: 90 degrees from AN_s
    ok = np.linalg.norm(turned, axis=1) > 0.5
    assert np.all(normal_angles(rec, turned)[ok] > 60)
    path = tmp_path / "scan.ply"
    _write_ply(path, pts, normals, colors, intensity)
    run = subprocess.run(
        [sys.executable, "-m", "crustview", "reconstruct", path, "-d", "auto", "-o", tmp_path / "r.npz"]
        + ["--report", tmp_path / "r.json"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    assert "File normals against AN_s: median angle" in run.stdout
    assert "-d auto chose d = 2 (a surface)" in run.stderr
    report = json.loads((tmp_path / "r.json").read_text())
    section = report["input_attributes"]
    assert section["colors"] and section["normals"] and section["intensity"] == {"min": 0.0, "max": 99.0}
    angles = section["normal_angles"]
    assert angles["n"] == N and angles["median_degrees"] < 5 and sum(angles["histogram"]["counts"]) == N
    assert report["dimension_estimate"]["d"] == 2 and report["dimension_estimate"]["confidence"] > 0.9


def test_a_pcd_whose_header_declares_too_many_points_is_one_error(tmp_path):
    head = "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2000000000\nHEIGHT 1\n"
    head += "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2000000000\nDATA binary\n"
    path = tmp_path / "huge.pcd"
    path.write_bytes(head.encode() + b"\0" * 24)
    with pytest.raises(InputError, match="declares 2000000000 points"):
        read_points(path)

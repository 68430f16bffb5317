"""crustview's own Wavefront OBJ reader: what real exports contain, checked on files small enough to read by eye."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from crustview.core import InputError
from crustview.io import read_attributes, read_points
from crustview.meshfiles import read_mesh

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"


def _write(tmp_path: Path, text: str, name: str = "m.obj") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_normals_and_textures_numbered_on_their_own(tmp_path):
    # 4 vertices, 2 normals, 5 texture coordinates: the face entries' second and third numbers index those lists
    text = SQUARE + "vn 0 0 1\nvn 0 0 -1\n" + "vt 0 0\n" * 5 + "f 1/5/2 2/4/1 3/3/2\nf 1//2 3//1 4//2\n"
    mesh = read_mesh(_write(tmp_path, text))
    assert mesh.points.shape == (4, 3)
    assert mesh.simplices(2).tolist() == [[0, 1, 2], [0, 2, 3]]


def test_relative_indices_count_back_from_the_latest_vertex(tmp_path):
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -3 -1\n"
    assert read_mesh(_write(tmp_path, text)).simplices(2).tolist() == [[0, 1, 2], [0, 1, 3]]


def test_polylines_become_segments_and_quads_fans(tmp_path):
    mesh = read_mesh(_write(tmp_path, SQUARE + "l 1 2 3 4 1\n"))
    assert mesh.simplices(1).tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]
    quad = read_mesh(_write(tmp_path, SQUARE + "f 1 2 3 4\n", "q.obj"))
    assert quad.simplices(2).tolist() == [[0, 1, 2], [0, 2, 3]]


def test_comments_continuations_weights_and_other_records(tmp_path):
    text = (
        "# exported\nmtllib a.mtl\no part\ng group\ns 1\nusemtl red\n"
        "v 0 0 0 1.0\nv 1 0 0 1.0\nv 0 1 \\\n 0 1.0  # a continued line\nvp 0.5\np 1\nf 1 2 3 # a comment\n"
    )
    mesh = read_mesh(_write(tmp_path, text))
    np.testing.assert_array_equal(mesh.points, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert mesh.simplices(2).tolist() == [[0, 1, 2]]


def test_vertex_colours_are_attributes(tmp_path):
    path = _write(tmp_path, "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 255\nf 1 2 3\n")
    colours = read_mesh(path).attributes["colors"]
    # one value above 1: the file's colours are 0..255, so every one is scaled by 255
    np.testing.assert_allclose(colours, [[1 / 255, 0, 0], [0, 1 / 255, 0], [0, 0, 1]])
    np.testing.assert_allclose(read_attributes(path)["colors"], colours)
    assert read_attributes(_write(tmp_path, SQUARE + "f 1 2 3\n", "plain.obj")) == {}
    assert read_points(path).shape == (3, 2)  # a flat file's zero z is dropped, as for every mesh format


@pytest.mark.parametrize(
    "text, fragment",
    [
        (SQUARE + "f 1 2 0\n", "vertex index 0"),
        (SQUARE + "f 1 2 9\n", "refers to vertex 9 but the file has 4 vertices (numbered 1 to 4 in OBJ)"),
        ("f 1 2 3\n", "it has faces but no vertices"),
        (SQUARE + "f -1 -2 -5\n", "goes back past the first vertex"),
        (SQUARE + "f 1 2\n", "at least three vertices"),
        (SQUARE + "f 1 two 3\n", "'two' is not a vertex index"),
        ("v 0 0\n", "three coordinates"),
        ("v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "vertex 1 has a value that is not a number"),
    ],
)
def test_bad_obj_files_are_one_sentence(tmp_path, text, fragment):
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as info:
        read_mesh(path)
    msg = str(info.value)
    assert fragment in msg and str(path) in msg and "\n" not in msg

"""The 2-faces of a Voronoi cell in R^4 (drawn as patches)."""

import itertools

import numpy as np

from crustview.scene.voronoi import clipped_cell


def test_the_4_cube_has_24_square_2_faces():
    cube = np.array(list(itertools.product([-1.0, 1.0], repeat=4)))
    got = clipped_cell(cube, np.zeros(4), -5 * np.ones(4), 5 * np.ones(4))
    assert got is not None
    verts, edges, tris = got
    assert len(verts) == 16 and len(edges) == 32
    assert len(tris) == 48  # 24 squares, two triangles each
    # every triangle lies in a 2-face: two of the coordinates are constant on it
    for t in verts[tris]:
        assert (np.ptp(t, axis=0) < 1e-9).sum() == 2
    u, v = verts[tris[:, 1]] - verts[tris[:, 0]], verts[tris[:, 2]] - verts[tris[:, 0]]
    uu, vv, uv = (u * u).sum(1), (v * v).sum(1), (u * v).sum(1)
    area = 0.5 * np.sqrt(uu * vv - uv**2).sum()
    assert np.isclose(area, 24 * 4.0)  # the squares are covered once, not folded

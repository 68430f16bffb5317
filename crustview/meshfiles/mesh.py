"""A mesh read from a file: its vertices and its faces, and the checks every reader shares."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from crustview.core.errors import InputError


@dataclass(frozen=True)
class MeshData:
    """Vertices and polygons read from a mesh file.

    Attributes
    ----------
    points : ndarray of shape (n, k)
    cells : list of ndarray
        Blocks of polygons, each of shape (m_i, s_i): s_i vertex indices
        (0-based, checked to be in range) per polygon.
    path : Path
    attributes : dict of str to ndarray
        Per-vertex values other than coordinates, by :mod:`crustview.attributes`
        name: ``colors`` (n, 3) in [0, 1], ``intensity`` (n,), ``normals`` (n, k).
    """

    points: np.ndarray
    cells: list[np.ndarray]
    path: Path
    attributes: dict = field(default_factory=dict)

    @property
    def n_cells(self) -> int:
        """Number of polygons in all blocks."""
        return int(sum(len(c) for c in self.cells))

    def fitting_dimensions(self) -> list[int]:
        """The d in 1 .. k-1 whose simplices the polygons can be (:meth:`simplices` takes them), ascending.

        Every block must fit: ``d + 1`` vertices per polygon, or for d = 2 any polygon of three or more (fanned
        into triangles).  Empty for a file without polygons.  Polygons of four vertices fit d = 2 (quads) and,
        in R^4 and up, d = 3 (tetrahedra): both are listed.
        """
        k = self.points.shape[1] if self.points.ndim == 2 else 0
        if not self.cells:
            return []
        return [d for d in range(1, k) if all(b.shape[1] == d + 1 or (d == 2 and b.shape[1] > 3) for b in self.cells)]

    def simplices(self, d: int) -> np.ndarray:
        """The polygons as d-simplices, shape (m, d + 1).

        For d = 2, polygons with more than three vertices (quads ...) are split
        into a fan of triangles from their first vertex, which is exact for
        convex planar polygons.  Otherwise every polygon must have exactly
        d + 1 vertices.

        Raises
        ------
        InputError
            Polygons of a size that does not fit ``d``, or with a repeated vertex.
        """
        out = []
        for block in self.cells:
            s = block.shape[1]
            if d == 2 and s > 3:
                fan = [block[:, [0, i, i + 1]] for i in range(1, s - 1)]
                out.append(np.stack(fan, axis=1).reshape(-1, 3))
            elif s == d + 1:
                out.append(block)
            else:
                what = {1: "1 vertex", 2: "2 vertices (segments)"}.get(s, f"{s} vertices")
                want = "segments (2 vertices)" if d == 1 else f"{d + 1} vertices" if d != 2 else "3 or more vertices"
                raise InputError(
                    f"Cannot use the faces of '{self.path}' for d = {d}: {len(block)} of them have {what}, "
                    f"but a {d}-manifold needs {want} per face."
                )
        simp = np.concatenate(out) if out else np.empty((0, d + 1), np.int64)
        srt = np.sort(simp, axis=1)
        rep = (srt[:, 1:] == srt[:, :-1]).any(axis=1)
        if rep.any():
            raise InputError(
                f"Cannot use the faces of '{self.path}': {int(rep.sum())} face(s) repeat a vertex "
                f"(the first is {tuple(int(v) for v in simp[np.flatnonzero(rep)[0]])}, counting from 0)."
            )
        return simp.astype(np.int64)


def _bad(path: Path, what: str) -> InputError:
    return InputError(f"Cannot read '{path}' as a {path.suffix.lower() or 'mesh'} mesh ({what}).")


def _blocks(polys: list[list[int]] | list[np.ndarray]) -> list[np.ndarray]:
    """Group polygons by size, keeping the order of first appearance."""
    by: dict[int, list] = {}
    for p in polys:
        by.setdefault(len(p), []).append(p)
    return [np.asarray(v, dtype=np.int64).reshape(len(v), s) for s, v in by.items()]


def _check_indices(cells: list[np.ndarray], n: int, path: Path) -> None:
    for block in cells:
        if len(block) and (block.min() < 0 or block.max() >= n):
            bad = int(block[(block < 0) | (block >= n)][0])
            if n == 0:
                raise _bad(path, "it has faces but no vertices")
            # an OBJ file counts its vertices from 1: its own numbers, as its author wrote them
            base = 1 if path.suffix.lower() == ".obj" else 0
            raise _bad(
                path,
                f"a face refers to vertex {bad + base} but the file has {n} vertices "
                f"(numbered {base} to {n - 1 + base}{' in OBJ' if base else ''})",
            )

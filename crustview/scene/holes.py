"""The holes of T_S as a reader sees them: rims, their patches and their size (Qt-free).

The *Holes of T_S* layer draws the (d-1)-faces of the candidate complex that
lie in a single simplex before extraction.  On a scan they come in loops
around the places the scanner missed, and drawn one by one they are long
edges across empty space.  Here they are grouped into rims (faces that share
a sample belong to one rim), each with its size: how many faces it has and
how far it reaches, in local sample spacings.  A surface's rim also gets a
patch, a fan of triangles from its centre to each rim edge, which the layer
shades faintly so the hole reads as an area.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Rims with more vertices than this get their span from a double farthest-point sweep.
EXACT_SPAN_VERTICES = 2000


@dataclass(frozen=True)
class HoleRim:
    """One hole of T_S: its rim faces and its size.

    Attributes
    ----------
    faces : ndarray of shape (e, d)
        The rim's (d-1)-faces, as sample indices.
    samples : ndarray of shape (v,)
        The samples on the rim (sorted).
    span : float
        The largest distance between two rim samples, in the median local
        spacing of those samples.
    centre : ndarray of shape (k,)
        The mean of the rim samples (where the patch's fan meets and the label sits).
    """

    faces: np.ndarray
    samples: np.ndarray
    span: float
    centre: np.ndarray

    @property
    def size(self) -> int:
        """Number of rim faces (edges for a surface)."""
        return len(self.faces)

    def words(self, d: int) -> str:
        """E.g. "48 rim edges, 12.3 spacings across"."""
        unit = {1: "end sample", 2: "rim edge", 3: "rim triangle"}.get(d, "rim face")
        return f"{self.size:,} {unit}{'' if self.size == 1 else 's'}, {self.span:.1f} spacings across"


def _diameter(x: np.ndarray) -> float:
    """The largest distance between two rows of ``x`` (a lower bound past :data:`EXACT_SPAN_VERTICES`)."""
    if len(x) < 2:
        return 0.0
    if len(x) <= EXACT_SPAN_VERTICES:
        from scipy.spatial.distance import pdist

        return float(pdist(x).max())
    a = x[np.argmax(np.linalg.norm(x - x[0], axis=1))]
    far = np.linalg.norm(x - a, axis=1)
    return float(far.max())


def hole_rims(faces: np.ndarray, points: np.ndarray, spacing: np.ndarray) -> list[HoleRim]:
    """Group the hole faces of T_S into rims, largest first.

    Parameters
    ----------
    faces : ndarray of shape (h, d)
        The (d-1)-faces of T_S in a single simplex (``SceneModel.holes``).
    points : ndarray of shape (n, k)
        The samples.
    spacing : ndarray of shape (n,)
        Each sample's local spacing (``SceneModel.spacing``).

    Returns
    -------
    list of HoleRim
        One per connected group of faces (faces sharing a sample are
        connected), by decreasing number of faces, then span.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    faces = np.asarray(faces, dtype=np.int64)
    if faces.ndim != 2 or len(faces) == 0:
        return []
    used, local = np.unique(faces, return_inverse=True)
    local = local.reshape(faces.shape)
    # each face joins its vertices: a path through them is enough for connectivity
    a = local[:, :-1].ravel()
    b = local[:, 1:].ravel()
    m = len(used)
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    face_label = label[local[:, 0]]
    order = np.argsort(face_label, kind="stable")
    bounds = np.flatnonzero(np.diff(face_label[order])) + 1
    rims = []
    for group in np.split(order, bounds):
        mine = faces[group]
        samples = np.unique(mine)
        x = points[samples]
        unit = float(np.median(spacing[samples])) or 1.0
        rims.append(HoleRim(mine, samples, _diameter(x) / unit, x.mean(axis=0)))
    rims.sort(key=lambda r: (-r.size, -r.span))
    return rims


def rim_patches(rims: list[HoleRim], n: int) -> tuple[np.ndarray, np.ndarray]:
    """The fan of each surface rim: triangles from its centre to each rim edge.

    Parameters
    ----------
    rims : list of HoleRim
        Rims of edges (d = 2); rims of other faces get no patch.
    n : int
        Number of samples: the centres are numbered ``n, n + 1, …`` after them.

    Returns
    -------
    centres : ndarray of shape (c, k)
        The centres of the rims that have a patch, to append to the samples.
    triangles : ndarray of shape (t, 3)
        Indices into the samples followed by ``centres``.
    """
    with_patch = [r for r in rims if r.faces.shape[1] == 2 and r.size >= 3]
    if not with_patch:
        k = rims[0].centre.shape[0] if rims else 0
        return np.zeros((0, k)), np.zeros((0, 3), dtype=np.int64)
    tris = [np.column_stack([np.full(r.size, n + j), r.faces]) for j, r in enumerate(with_patch)]
    return np.array([r.centre for r in with_patch]), np.vstack(tris).astype(np.int64)


def holes_summary(rims: list[HoleRim], d: int) -> str:
    """The legend's line, e.g. "Holes of T_S: 112 (largest 48 rim edges, 12.3 spacings across)"."""
    if not rims:
        return "Holes of T_S: none"
    head = f"Holes of T_S: {len(rims):,}"
    return f"{head} (largest {rims[0].words(d)})"

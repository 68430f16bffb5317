"""Naming a closed manifold from its topology (Qt-free).

The classification of closed surfaces needs only the Z/2 Betti numbers and
orientability: a connected orientable surface with b1 = 2g is the genus-g
surface; a non-orientable one with b1 = h (over Z/2) is the connected sum of
h projective planes (h = 1 the projective plane, h = 2 the Klein bottle).
Closed curves are circles.  In dimension 3 the Z/2 Betti numbers of S^3,
(1, 0, 0, 1), say only "a Z/2-homology 3-sphere", and the name says so.
"""

from __future__ import annotations


def surface_name(orientable: bool | None, b1: int) -> str:
    """Name of a connected closed surface with Z/2 first Betti number ``b1``."""
    if orientable or orientable is None:
        g = b1 // 2
        return {0: "sphere", 1: "torus"}.get(g, f"genus-{g} surface")
    return {1: "projective plane", 2: "Klein bottle"}.get(
        b1, f"non-orientable surface of genus {b1} (sum of {b1} projective planes)"
    )


def shape_name(d: int, betti: tuple[int, ...], orientable: bool | None, closed: bool = True) -> str:
    """A name for a closed d-manifold with Z/2 Betti numbers ``betti``.

    Parameters
    ----------
    d : int
        Dimension.
    betti : tuple of int
        Z/2 Betti numbers b0 .. bd.
    orientable : bool or None
    closed : bool
        False: the complex is not a closed manifold, and the name says so.

    Examples
    --------
    >>> shape_name(2, (1, 2, 1), False)
    'Klein bottle'
    >>> shape_name(1, (2, 2), True)
    '2 circles'
    """
    if not closed:
        return "not a closed manifold"
    b = tuple(int(v) for v in betti)
    if not b or b[0] == 0:
        return "empty"
    if d == 1:
        return "circle" if b[0] == 1 else f"{b[0]} circles"
    if b[0] > 1:
        return f"{b[0]} closed {d}-manifolds"
    if d == 2:
        return surface_name(orientable, b[1] if len(b) > 1 else 0)
    if d == 3 and b == (1, 0, 0, 1):
        return "S³ (a Z/2-homology 3-sphere)"
    return f"closed {d}-manifold with Z/2 Betti numbers {', '.join(map(str, b))}"


def name_of(topology, d: int) -> str:
    """:func:`shape_name` of a :class:`~crustview.core.result.TopologyReport`."""
    return shape_name(d, tuple(topology.betti), topology.orientable, bool(topology.closed_manifold))

"""The handles cut-handle removes, real or not on the true mesh: the sweep behind its band [LOOP_MIN, CUT_BELOW).

For every closed mesh of ``../shared/data/scans`` and ``../shared/data/scans2`` (or those named with
``--only``) and, with ``--noise``, its noisy copies (0.1 h and 0.3 h, as ``bench_scans.py`` makes them), the
robust extraction is run and every cut of the rule ``cut-handle`` is listed: its loop in sampling radii,
whether that is in the band where the cut stays uncertain, how it was cut (``fill``: outside cells made
inside; ``cut``: inside cells made outside), its cells, their labelling confidence, how far the faces it
added reach from the loop's centroid over the loop's reach (``cut_handle.reach``; the sweep behind
``CUT_REACH``), and whether the handle was *real*: whether the removed loop (its samples are the mesh's own
vertices) is non-trivial in the Z/2 homology of the mesh's own faces.  The last lines give the largest reach
and, per kind, the range of the loops in the band.

The test of a loop: a spanning tree of the mesh's edges and a spanning tree of the dual graph through the
other edges (tree-cotree) leave 2g edges; each, with the dual tree's path between its two faces, is a
cycle of the dual graph, and the mesh edges it crosses are a cocycle.  A loop is non-trivial exactly when it
crosses some such cocycle an odd number of times (consecutive loop samples that are not a mesh edge are
joined by a shortest path of the mesh).

With ``--decimate SHARE`` the meshes are first decimated as ``bench_scans.py --decimate`` does (long thin
triangles where they are flat); the true mesh is then the decimated one.  With ``--no-reach`` the rule runs
without its reach bound (``CUT_REACH`` set to infinity), to see the cuts the bound refuses.

Run: ``python benchmarks/bench_cuts.py [--only NAME ...] [--noise [--seed N]] [--decimate SHARE] [--no-reach]``;
about a minute per closed mesh.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components, minimum_spanning_tree, shortest_path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_scans import FOLDERS, cases  # noqa: E402

import crustview.core.robust.cells as cells  # noqa: E402
import crustview.core.robust.cut_handle as cut_handle  # noqa: E402
from crustview.core import reconstruct  # noqa: E402
from crustview.core.analysis.features import LOOP_MIN  # noqa: E402
from crustview.core.robust.cut_handle import CUT_BELOW, reach  # noqa: E402
from crustview.io import read_mesh  # noqa: E402


class Cocycles:
    """Z/2 cocycles of a closed triangle mesh that detect every non-trivial loop (tree-cotree)."""

    def __init__(self, n: int, faces: np.ndarray) -> None:
        self.n = n
        e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [0, 2]]]), axis=1).astype(np.int64)
        keys, inverse = np.unique(e[:, 0] * n + e[:, 1], return_inverse=True)
        self.index = {int(k): i for i, k in enumerate(keys)}
        edges = np.c_[keys // n, keys % n]
        nf = len(faces)
        face_edges = inverse.reshape(3, nf).T
        graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
        self.graph = graph + graph.T
        tree = minimum_spanning_tree(self.graph).tocoo()
        in_tree = {self._edge(a, b) for a, b in zip(tree.row.tolist(), tree.col.tolist(), strict=True)}
        owners: list[list[int]] = [[] for _ in range(len(edges))]
        for f in range(nf):
            for i in face_edges[f].tolist():
                owners[i].append(f)
        dual = [(o[0], o[1], i) for i, o in enumerate(owners) if i not in in_tree and len(o) == 2]
        across = {}
        for a, b, i in dual:
            across[(a, b)] = across[(b, a)] = i
        g = coo_matrix((np.ones(len(dual)), ([a for a, _, _ in dual], [b for _, b, _ in dual])), shape=(nf, nf))
        cotree = minimum_spanning_tree((g + g.T).tocsr()).tocoo()
        in_cotree = {across[(a, b)] for a, b in zip(cotree.row.tolist(), cotree.col.tolist(), strict=True)}
        t = coo_matrix((np.ones(len(cotree.row)), (cotree.row, cotree.col)), shape=(nf, nf)).tocsr()
        # one search per part of the mesh (each part's faces are one tree of the dual forest)
        _, part = connected_components(t, directed=False)
        parent = np.full(nf, -1, np.int64)
        depth = np.zeros(nf, np.int64)
        for root in np.unique(part, return_index=True)[1].tolist():
            order, pred = breadth_first_order(t + t.T, root, directed=False, return_predecessors=True)
            parent[order[1:]] = pred[order[1:]]
            for f in order[1:].tolist():
                depth[f] = depth[parent[f]] + 1
        self.cocycles: list[set[int]] = []
        for a, b, i in dual:
            if i in in_cotree:
                continue
            crossed, x, y = {i}, a, b
            while x != y:
                if depth[x] < depth[y]:
                    x, y = y, x
                crossed ^= {across[(x, int(parent[x]))]}
                x = int(parent[x])
            self.cocycles.append(crossed)

    def _edge(self, a: int, b: int) -> int:
        return self.index[min(a, b) * self.n + max(a, b)]

    def nontrivial(self, loop: list[int]) -> bool | None:
        """Whether the closed loop of mesh vertices is non-trivial in H_1(mesh; Z/2); None when two of its
        consecutive samples lie on different parts of the mesh (the loop is no cycle of it)."""
        edges: dict[int, int] = {}
        for u, v in zip(loop, loop[1:] + loop[:1], strict=True):
            if u == v:  # a loop listed with its first sample again at the end
                continue
            key = min(u, v) * self.n + max(u, v)
            if key in self.index:
                path = [self.index[key]]
            else:  # not a mesh edge: the mesh's shortest path
                _, pred = shortest_path(self.graph, indices=[u], unweighted=True, return_predecessors=True)
                if pred[0][v] < 0:
                    return None
                path, x = [], v
                while x != u:
                    path.append(self._edge(int(pred[0][x]), x))
                    x = int(pred[0][x])
            for i in path:
                edges[i] = edges.get(i, 0) ^ 1
        odd = {i for i, bit in edges.items() if bit}
        return any(len(odd & c) % 2 for c in self.cocycles)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="file stems")
    ap.add_argument("--noise", action="store_true", help="also the noisy copies at 0.1 h and 0.3 h")
    ap.add_argument("--seed", type=int, default=0, help="noisy.py's seed: 0 the public draws, others held out")
    ap.add_argument("--noisy-dir", type=Path, help="cache of noisy copies (default benchmarks/.noisy[-sSEED])")
    ap.add_argument("--decimate", type=float, metavar="SHARE", help="decimate each mesh to this share of its faces")
    ap.add_argument("--no-reach", action="store_true", help="run cut-handle without its reach bound")
    args = ap.parse_args(argv)
    if args.decimate is not None and not 0 < args.decimate < 1:
        ap.error("--decimate takes a share in (0, 1)")
    if args.no_reach:
        cut_handle.CUT_REACH = float("inf")
    here = Path(__file__).resolve().parent
    noisy_dir = args.noisy_dir or (here / (".noisy" if args.seed == 0 else f".noisy-s{args.seed}"))
    seen: list = []
    run_cuts = cells.cut_handles

    def spy(ed, points, cancel=None):
        out = run_cuts(ed, points, cancel)
        seen.append((ed.lab, points, out))
        return out

    cells.cut_handles = spy
    real_band, false_band = [], []
    print("| file | loop (radii) | band | how | cells | mean confidence | reach | real on the mesh |")
    print("|---|---|---|---|---|---|---|---|")
    only = set(args.only) if args.only else None
    todo = [c for c in cases(args.noise, only, noisy_dir, args.seed, decimate=args.decimate) if c.truth["closed"]]
    reached: list[float] = []
    meshes: dict[str, Cocycles] = {}
    for case in todo:
        stem = case.name.split("-n")[0]
        if stem not in meshes:
            if case.tris is not None:  # the case's own mesh (the decimated one where it was decimated)
                meshes[stem] = Cocycles(len(case.points), np.asarray(case.tris, np.int64))
            else:
                path = next(
                    f for folder in FOLDERS for f in folder.glob(stem + ".*") if f.suffix in (".off", ".obj", ".ply")
                )
                mesh = read_mesh(path)
                meshes[stem] = Cocycles(len(mesh.points), np.asarray(mesh.simplices(2), np.int64))
        seen.clear()
        rec = reconstruct(case.points, 2, resample=False)
        for lab, points, result in seen:
            for cut in result.cuts:
                ring = points[cut.feature.vertices]
                vs = np.unique(lab.faces[cut.added])
                vs = vs[vs < lab.n]
                far = float(np.linalg.norm(points[vs] - ring.mean(axis=0), axis=1).max()) if len(vs) else 0.0
                reached.append(far / reach(cut.feature, ring))
                loop = [int(v) for v in rec.point_input[cut.feature.vertices]]
                real = meshes[stem].nontrivial(loop)
                said = {True: "yes", False: "no", None: "no (the loop joins parts of the mesh)"}[real]
                real = bool(real)
                size = cut.feature.size_spacings
                band = LOOP_MIN <= size < CUT_BELOW
                if band:
                    (real_band if real else false_band).append(size)
                conf = float(lab.confidence[cut.cells].mean())
                print(
                    f"| {case.name} | {size:.2f} | {'yes' if band else 'no'} | {cut.how} | {len(cut.cells)} | "
                    f"{conf:.2f} | {reached[-1]:.2f} | {said} |",
                    flush=True,
                )
    cells.cut_handles = run_cuts
    print()
    if reached:
        print(f"cuts: {len(reached)}; their added faces reach at most {max(reached):.2f} times the loop's reach")
    for kind, sizes in (("real handles cut in the band", real_band), ("false handles cut in the band", false_band)):
        if sizes:
            print(f"{kind}: {len(sizes)}, loops {min(sizes):.2f}-{max(sizes):.2f} radii")
        else:
            print(f"{kind}: none")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""``crustview compare A B [--json OUT]``: two complexes simplex by simplex, and their Hausdorff distance.

An operand is a file, optionally followed by ``@key=value,...``:

* a saved result ``.npz``: its M_S;
* a mesh file with faces (``.off``, ``.ply``, ``.obj`` ...): its faces (d from them: polygons a
  surface, segments a curve);
* a point file: M_S of a reconstruction (``d`` is needed: ``-d`` or ``@d=2``);
* any of them with ``@test=literal``, ``@theta=30`` (degrees), ``@mode=paper``
  or ``@d=2``: M_S of the file's points reconstructed with those settings
  (a result ``.npz`` starts from its own d, test, θ and pruning).
"""

from __future__ import annotations

import argparse
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .core.errors import InputError

_KEYS = ("test", "theta", "mode", "d")


@dataclass
class Operand:
    """One side of a comparison: points, simplices and what they are."""

    label: str
    points: np.ndarray
    simplices: np.ndarray
    d: int


def parse_operand(text: str) -> tuple[Path, dict]:
    """``PATH[@key=value,...]`` to the path and the settings."""
    path, _, spec = text.partition("@")
    opts: dict = {}
    for item in filter(None, (s.strip() for s in spec.split(","))):
        key, eq, value = item.partition("=")
        if not eq or key not in _KEYS:
            raise InputError(f"'{item}' in '{text}': use @test=..., @theta=DEG, @mode=robust|paper or @d=N")
        try:
            opts[key] = int(value) if key == "d" else float(value) if key == "theta" else value
        except ValueError:
            raise InputError(f"'{item}' in '{text}' is not a number") from None
    return Path(path), opts


def _mesh_d(mesh) -> int | None:
    """The dimension a mesh's faces say: polygons of three vertices or more a surface, segments a curve."""
    sizes = {int(block.shape[1]) for block in mesh.cells if len(block)}
    if sizes and min(sizes) >= 3:
        return 2
    return 1 if sizes == {2} else None


def load_operand(text: str, d: int | None) -> Operand:
    """Read (and if asked, reconstruct) one operand; see the module docstring."""
    from .core import reconstruct
    from .io import read_mesh, read_points, read_run_parameters

    path, opts = parse_operand(text)
    if not path.exists():
        raise InputError(f"'{path}' does not exist")
    params = read_run_parameters(path)
    mesh = read_mesh(path) if params is None else None
    points = mesh.points if mesh is not None else read_points(path)
    dd = opts.get("d") or (params["d"] if params else None) or d or (_mesh_d(mesh) if mesh is not None else None)
    if dd is None:
        raise InputError(f"give d for '{path.name}' (-d N or {path.name}@d=N)")
    if params is not None and not opts:
        return Operand(f"{path.name} (saved M_S)", points, params["simplices"], dd)
    if mesh is not None and not opts:
        return Operand(f"{path.name} (mesh faces)", points, mesh.simplices(dd), dd)
    kw = {"test": "cocone", "theta": math.pi / 8, "prune_boundary": True, "mode": "robust"}
    if params is not None:
        kw.update(test=params["test"], theta=params["theta"], prune_boundary=params["prune_boundary"])
        kw["labelling"] = params.get("labelling", True)
    kw.update({k: v for k, v in opts.items() if k in ("test", "mode")})
    if "theta" in opts:
        kw["theta"] = math.radians(opts["theta"])
    rec = reconstruct(points, dd, **kw)
    label = f"{path.name} (M_S: {kw['test']}, θ = {math.degrees(kw['theta']):.4g}°, {kw['mode']})"
    return Operand(label, rec.input_points, rec.manifold_input_simplices(), dd)


def add_parser(sub) -> None:
    """Register ``compare`` on the sub-parsers action ``sub``."""
    p = sub.add_parser("compare", help="compare two results, meshes or runs: common simplices and Hausdorff distance")
    p.add_argument("a", help="A: result .npz, mesh file, or point file[@test=..,theta=..,mode=..,d=..]")
    p.add_argument("b", help="B: the same kinds as A")
    p.add_argument("-d", type=int, default=None, help="intrinsic dimension when a point file does not say")
    p.add_argument("--json", type=Path, default=None, help="also write the counts to this JSON file")


def run(args: argparse.Namespace) -> int:
    """Run ``crustview compare``; prints one summary and returns 0."""
    from .cli_reconstruct import check_outputs
    from .core.analysis.complexdiff import diff_complexes

    if args.json is not None:  # before the work: never over A's or B's file, never in a missing folder
        check_outputs([Path(str(x).split("@", 1)[0]) for x in (args.a, args.b)], [args.json], False, hint=False)
    a = load_operand(args.a, args.d)
    b = load_operand(args.b, args.d)
    if a.d != b.d:
        raise InputError(f"A is {a.d}-dimensional and B {b.d}-dimensional: give the same d")
    diff = diff_complexes(a.points, a.simplices, b.points, b.simplices, a.d)
    out = {"a": a.label, "b": b.label, "d": a.d, **diff.counts()}
    h = diff.hausdorff
    if diff.matched:
        words = f"{len(diff.both)} simplices in both, {len(diff.only_a)} only in A, {len(diff.only_b)} only in B"
    else:
        words = "the two do not share vertices, so only the distance is compared"
    same = diff.matched and not len(diff.only_a) and not len(diff.only_b)
    distance = "0 (the same simplices)" if same else h.words()
    print(f"A = {a.label}: {len(a.simplices)} simplices; B = {b.label}: {len(b.simplices)} simplices")
    print(
        f"{words}; Hausdorff distance {distance} (A to B {h.a_to_b:.4g}, "
        f"B to A {h.b_to_a:.4g}; sampled on grids over both complexes, ± their covering radius {h.error_bound:.2g})."
    )
    if args.json is not None:
        from crustview.atomic import write_text

        try:
            write_text(args.json, json.dumps(out, indent=2, default=float) + "\n")
        except OSError as err:
            raise InputError(f"Cannot write '{args.json}': {err.strerror or err}.") from None
    return 0

"""Fuzzing the readers: seeds of every format, byte mutations, and the check each case must pass.

Used by ``tests/test_fuzz_readers.py`` (a few thousand cases per reader) and
``scripts/fuzz_readers.py`` (as many as you like).  A case is a byte string
written to a file with the reader's suffix; the reader must return a valid
point set (or mesh, or session) or raise one :class:`CrustviewError` whose
message is one line.  Anything else fails, and so does a case that runs
longer than :data:`TIME_LIMIT` seconds or allocates more than
:data:`MEMORY_LIMIT` bytes (traced by ``tracemalloc``, which sees numpy's
allocations).
"""

from __future__ import annotations

import functools
import io
import json
import re
import signal
import tempfile
import tracemalloc
import zipfile
from pathlib import Path

import numpy as np

# hypothesis is imported only where its strategies are built (``scripts/fuzz_readers.py``): the test
# suite's cases come from numpy's generator, and importing hypothesis here made pytest rewrite the
# asserts of its ~100 modules (it is a pytest plugin's package) in every xdist process, about 1 s each.

#: Seconds one case may take.
TIME_LIMIT = 5.0
#: Bytes one case may allocate (the files are a few kilobytes).
MEMORY_LIMIT = 256 * 2**20

#: Reader name -> file suffix.
READERS = {
    "text": ".xyz",
    "csv": ".csv",
    "ply-ascii": ".ply",
    "ply-binary": ".ply",
    "off": ".off",
    "noff": ".noff",
    "off-binary": ".off",
    "obj": ".obj",
    "npy": ".npy",
    "npz": ".npz",
    "session": ".crustview.json",
    "pcd": ".pcd",
    "las": ".las",
    "laz": ".laz",
    "e57": ".e57",
}


class Hang(Exception):
    """A case ran longer than :data:`TIME_LIMIT`."""


def _points(n=12, k=3, seed=0):
    return np.random.default_rng(seed).normal(size=(n, k)).round(4)


def _tris(n=12, m=8, seed=0):
    rng = np.random.default_rng(seed)
    return np.array([rng.choice(n, 3, replace=False) for _ in range(m)])


def _via_file(suffix: str, write) -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"seed{suffix}"
        write(path)
        return path.read_bytes()


def seeds(reader: str) -> list[bytes]:
    """Valid files of this reader's format (written by crustview or by the format's own library)."""
    from crustview.io import write_points
    from crustview.meshfiles.off import write_off
    from crustview.meshfiles.ply import write_ply

    pts, tri = _points(), _tris()
    if reader == "text":
        return [b"x y z\n" + b"".join(b"%g %g %g\n" % tuple(p) for p in pts), b"# c\n1 2\n3 4\n5 6\n"]
    if reader == "csv":
        return [_via_file(".csv", lambda p: write_points(p, pts)), b'"x","y"\n1,2\n3,4\n']
    if reader == "ply-ascii":
        return [_via_file(".ply", lambda p: write_ply(p, pts, tri, binary=False)), _plyfile(pts, text=True)]
    if reader == "ply-binary":
        big = _plyfile(pts, text=False, byte_order=">")
        return [_via_file(".ply", lambda p: write_ply(p, _points(k=5), tri)), _plyfile(pts, text=False), big]
    if reader == "off":
        coloured = b"COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0\n0 1 0\n3 0 1 2\n"
        return [_via_file(".off", lambda p: write_off(p, pts, tri)), coloured]
    if reader == "noff":
        return [_via_file(".noff", lambda p: write_off(p, _points(k=4), tri, ndim=True))]
    if reader == "off-binary":
        return [_off_binary(pts, tri)]
    if reader == "obj":
        from crustview.io import _write_obj

        return [_via_file(".obj", lambda p: _write_obj(p, pts, "triangle", tri))]
    if reader == "npy":
        buf = io.BytesIO()
        np.save(buf, pts)
        return [buf.getvalue()]
    if reader == "npz":
        buf = io.BytesIO()
        np.savez_compressed(buf, points=pts)
        plain = io.BytesIO()
        np.savez(plain, points=pts, other=np.arange(3))
        return [buf.getvalue(), plain.getvalue()]
    if reader == "session":
        from crustview.session import BuiltinSource, Session

        return [json.dumps(Session(BuiltinSource("torus", 1500, 3), d=2).to_dict(), indent=1).encode()]
    if reader == "pcd":
        return [_pcd(pts, enc) for enc in ("ascii", "binary", "binary_compressed")]
    if reader in ("las", "laz"):
        return [_las(pts, reader)]
    if reader == "e57":
        return [_e57(pts)]
    raise KeyError(reader)


def _plyfile(pts, text, byte_order="<"):
    from plyfile import PlyData, PlyElement

    vert = np.zeros(len(pts), dtype=[(c, "f4") for c in ("x", "y", "z", "nx", "ny", "nz")] + [("red", "u1")] * 0)
    for i, c in enumerate("xyz"):
        vert[c] = pts[:, i]
    vert["nx"] = 1.0
    faces = np.zeros(3, dtype=[("vertex_indices", "i4", (3,))])
    faces["vertex_indices"] = _tris(m=3)
    data = PlyData([PlyElement.describe(vert, "vertex"), PlyElement.describe(faces, "face")], text=text)
    data.byte_order = byte_order
    buf = io.BytesIO()
    data.write(buf)
    return buf.getvalue()


def _off_binary(pts, tri):
    out = b"OFF BINARY\n" + np.array([len(pts), len(tri), 0], ">i4").tobytes() + pts.astype(">f4").tobytes()
    for t in tri:
        out += np.array([3, *t, 0], ">i4").tobytes()
    return out


def _pcd(pts, encoding):
    import pypcd4

    pc = pypcd4.PointCloud.from_xyz_points(pts.astype(np.float32))
    buf = io.BytesIO()
    pc.save(buf, encoding=pypcd4.Encoding(encoding))
    return buf.getvalue()


def _las(pts, kind):
    import laspy

    las = laspy.LasData(laspy.LasHeader(point_format=3, version="1.2"))
    las.header.scales = np.array([1e-3] * 3)
    las.header.offsets = np.zeros(3)
    las.x, las.y, las.z = pts.T
    las.intensity = np.arange(len(pts), dtype=np.uint16)
    return _via_file(f".{kind}", lambda p: las.write(p))


def _e57(pts):
    import pye57

    def write(path):
        e57 = pye57.E57(str(path), mode="w")
        e57.write_scan_raw({"cartesianX": pts[:, 0], "cartesianY": pts[:, 1], "cartesianZ": pts[:, 2]})
        e57.close()

    return _via_file(".e57", write)


# ---------------------------------------------------------------- mutations
_NUMBER = re.compile(rb"-?\d+")
_BIG = [b"0", b"-1", b"1", b"7", b"255", b"65536", b"2147483647", b"4294967295", b"99999999999", b"1e308"]


class _Draws:
    """The choices a mutation makes, from hypothesis (``draw``) or from a seeded numpy generator."""

    def __init__(self, draw=None, rng: np.random.Generator | None = None):
        self.draw, self.rng = draw, rng

    @staticmethod
    @functools.lru_cache(maxsize=4096)
    def _strategy(kind: str, *args):
        # a strategy built for every draw cost more than the draw: build each one once
        from hypothesis import strategies as st

        if kind == "binary":
            return st.binary(min_size=args[0], max_size=args[1])
        return {"integers": st.integers, "sampled_from": st.sampled_from}[kind](*args)

    def integer(self, lo: int, hi: int) -> int:
        """An integer in [lo, hi]; the numpy generator takes an end one time in eight, as hypothesis
        favours bounds."""
        if self.draw is not None:
            return self.draw(self._strategy("integers", lo, hi))
        if hi > lo and self.rng.random() < 0.125:
            return lo if self.rng.random() < 0.5 else hi
        return int(self.rng.integers(lo, hi + 1))

    def choice(self, options: list):
        if self.draw is not None:
            return self.draw(self._strategy("sampled_from", tuple(options)))
        return options[int(self.rng.integers(len(options)))]

    def binary(self, lo: int, hi: int) -> bytes:
        if self.draw is not None:
            return self.draw(self._strategy("binary", lo, hi))
        return self.rng.bytes(self.integer(lo, hi))


_OPS = ["flip", "cut", "insert", "number", "repeat", "int32"]
_INT32 = [b"\xff\xff\xff\x7f", b"\x7f\xff\xff\xff", b"\xff\xff\xff\xff"]


def mutate(seed: bytes, draws: _Draws) -> bytes:
    """``seed`` with a few mutations: flipped, cut, inserted or repeated bytes, numbers made huge or odd."""
    data = bytearray(seed)
    for _ in range(draws.integer(1, 6)):
        op = draws.choice(_OPS)
        n = len(data)
        if op == "flip" and n:
            i = draws.integer(0, n - 1)
            data[i] = draws.integer(0, 255)
        elif op == "cut" and n:
            i = draws.integer(0, n)
            j = draws.integer(i, min(n, i + 64))
            if draws.choice([True, False]):
                del data[i:j]
            else:
                del data[i:]
        elif op == "insert":
            i = draws.integer(0, n)
            data[i:i] = draws.binary(1, 16)
        elif op == "number":
            head = bytes(data[:600])
            found = list(_NUMBER.finditer(head))
            if found:
                m = found[draws.integer(0, len(found) - 1)]
                data[m.start() : m.end()] = draws.choice(_BIG)
        elif op == "repeat" and n:
            i = draws.integer(0, n - 1)
            data[i:i] = data[i : i + draws.integer(1, 32)] * draws.integer(1, 8)
        elif op == "int32" and n >= 4:  # a binary count or size made huge
            i = draws.integer(0, n - 4)
            data[i : i + 4] = draws.choice(_INT32)
    return bytes(data)


@functools.cache
def _mutated_strategy():
    from hypothesis import strategies as st

    @st.composite
    def mutated(draw, seed: bytes) -> bytes:
        return mutate(seed, _Draws(draw=draw))

    return mutated


def mutated(seed: bytes):
    """The hypothesis strategy of :func:`mutate` (``scripts/fuzz_readers.py``: fresh cases, shrunk on failure)."""
    return _mutated_strategy()(seed)


def cases(reader: str):
    """The strategy of one reader's cases: mutated seeds, mostly, and plain random bytes."""
    from hypothesis import strategies as st

    pool = seeds(reader)
    return st.one_of(
        st.sampled_from(pool).flatmap(mutated),
        st.sampled_from(pool).flatmap(mutated),
        st.sampled_from(pool).flatmap(mutated),
        st.binary(max_size=600),
    )


def seeded_cases(reader: str, n: int, seed: int = 0):
    """``n`` cases of the same kinds as :func:`cases`, three in four a mutated seed and one in four plain
    random bytes, from numpy's generator with a fixed ``seed``.

    The test suite's cases: hypothesis spent about 1.8 ms drawing each case (3.7 s of every reader's
    2,000), more than most readers take to check it; the generator takes a few microseconds.
    """
    pool = seeds(reader)
    rng = np.random.default_rng([seed, *reader.encode()])
    draws = _Draws(rng=rng)
    for _ in range(n):
        if rng.random() < 0.25:
            yield draws.binary(0, 600)
        else:
            yield mutate(pool[int(rng.integers(len(pool)))], draws)


# ---------------------------------------------------------------- the check
def _alarm(signum, frame):
    raise Hang(f"a case ran longer than {TIME_LIMIT} s")


def check_case(reader: str, data: bytes, folder: Path) -> str:
    """Run the reader on ``data``; returns "ok" or "error", raises on anything else."""
    from crustview.core.errors import CrustviewError

    path = folder / f"case{READERS[reader]}"
    # a new file each time: writing over the last case's file truncates it, and ext4 then flushes it to disk
    # on close (0.7 ms a case here, 0.05 ms for a new file; longer while other processes write)
    path.unlink(missing_ok=True)
    path.write_bytes(data)
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, TIME_LIMIT)
    tracemalloc.start()
    try:
        _read(reader, path)
        outcome = "ok"
    except CrustviewError as err:
        text = str(err)
        assert text and "\n" not in text, f"not one line: {text!r}"
        outcome = "error"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert peak <= MEMORY_LIMIT, f"allocated {peak / 2**20:.0f} MiB for a {len(data)}-byte file"
    return outcome


def _read(reader: str, path: Path) -> None:
    if reader == "session":
        from crustview.session import Session, read_session

        assert isinstance(read_session(path), Session)
        return
    from crustview.io import read_mesh, read_points

    attributes: dict = {}
    points = read_points(path, [], attributes)
    assert isinstance(points, np.ndarray) and points.dtype == np.float64 and points.ndim == 2
    assert len(points) >= 1 and points.shape[1] >= 2 and np.isfinite(points).all()
    for value in attributes.values():
        assert len(value) == len(points)
    if READERS[reader] in (".ply", ".off", ".noff", ".obj"):
        mesh = read_mesh(path)
        assert mesh is None or mesh.points.ndim == 2


def zip_of(members: dict[str, bytes]) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for name, data in members.items():
            z.writestr(name, data)
    return buf.getvalue()

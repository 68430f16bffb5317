"""NumPy point files: ``.npy`` (a 2-D array) and ``.npz`` (key ``points``), read without trusting their headers.

numpy allocates the shape a header declares before it reads the data, so a
few damaged bytes could ask for terabytes; these readers compare the
declared size with what the file (or the zip member) holds first.  Every
failure is one :class:`~crustview.core.errors.InputError` naming the file.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np

from crustview.core.errors import InputError
from crustview.textpoints import check_signature


def _reason(err: BaseException) -> str:
    text = " ".join(str(err).split()) or type(err).__name__
    if isinstance(err, OSError) and err.strerror:
        text = err.strerror
    text = text.rstrip(".")
    return text if len(text) <= 160 else text[:157] + "..."


def _npy_header(fh) -> tuple[tuple, np.dtype]:
    """Shape and dtype from a ``.npy`` header; only the versions numpy writes (1.0, 2.0, 3.0)."""
    version = np.lib.format.read_magic(fh)
    if version not in ((1, 0), (2, 0), (3, 0)):
        raise ValueError(f"unknown .npy format version {version[0]}.{version[1]}")
    read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    shape, _, dtype = read(fh)
    return shape, dtype


def read_npy(path: Path) -> Any:
    check_signature(path, "npy")
    try:
        data = path.read_bytes()  # in memory: a damaged header's lengths cannot make a read allocate more
        fh = io.BytesIO(data)
        shape, dtype = _npy_header(fh)
        needed = int(np.prod(shape, dtype=object)) * dtype.itemsize
        if needed > len(data) - fh.tell():  # numpy would allocate the declared shape before reading
            raise InputError(
                f"Cannot read '{path}': a damaged NumPy .npy file (its header declares shape {tuple(shape)}, "
                f"more than its {len(data)} bytes hold)."
            )
        fh.seek(0)
        return np.load(fh, allow_pickle=False)
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001 - any failure becomes one InputError
        if "allow_pickle" in str(err):  # an object array: numpy would need to unpickle it
            raise InputError(f"Cannot read '{path}': it holds Python objects, not an array of numbers.") from None
        raise InputError(f"Cannot read '{path}': a damaged NumPy .npy file ({_reason(err)}).") from None


def _check_npz_member(path: Path) -> None:
    """Refuse a ``points`` array whose header declares more data than the archive holds.

    numpy allocates the declared shape before reading a member of a zip
    archive, so a few bytes could otherwise ask for terabytes.  Deflate
    shrinks data at most about 1032 times.
    """
    import zipfile

    with zipfile.ZipFile(path) as archive:
        info = next((i for i in archive.infolist() if i.filename in ("points.npy", "points")), None)
        if info is None:
            return
        with archive.open(info) as member:
            shape, dtype = _npy_header(io.BytesIO(member.read(1 << 16)))
    needed = int(np.prod(shape, dtype=object)) * dtype.itemsize
    if needed > info.file_size or info.file_size > 1100 * info.compress_size + 4096:
        raise InputError(
            f"Cannot read '{path}': its 'points' array declares shape {tuple(shape)}, "
            f"more than the archive's {info.compress_size} bytes hold."
        )


def read_npz(path: Path) -> Any:
    check_signature(path, "npz")
    try:
        _check_npz_member(path)
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001
        raise InputError(f"Cannot read '{path}' as a NumPy .npz archive ({_reason(err)}).") from None
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as archive:
            keys = list(archive.keys())
            if "points" not in keys:
                raise InputError(
                    f"Cannot read '{path}': the archive has no 'points' array "
                    f"(it holds {', '.join(keys) or 'nothing'})."
                )
            return archive["points"]
    except InputError:
        raise
    except Exception as err:  # noqa: BLE001
        if "allow_pickle" in str(err):
            raise InputError(f"Cannot read '{path}': its 'points' hold Python objects, not numbers.") from None
        raise InputError(f"Cannot read '{path}' as a NumPy .npz archive ({_reason(err)}).") from None

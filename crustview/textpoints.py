"""Delimited text point files (``.csv .txt .xyz``) and the NumPy file signatures.

A text point file holds one point per line, its coordinates separated by
commas, semicolons or white space; ``#`` starts a comment line.  The first
line may instead name the columns (``x, y, z`` or ``"x","y","z"``): it is
accepted as a header only when every entry is a column name and there are
as many names as the data has columns, and the reader says that it skipped
it.  Any other line that is not all numbers is an error naming its line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from crustview.core.errors import InputError

_SPLIT = re.compile(r"[,;\s]+")
#: A column name: a letter or underscore, then letters, digits, underscores or dots (``x``, ``nx``, ``x_1``).
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]*$")

#: The first bytes of every ``.npy`` file.
NPY_MAGIC = b"\x93NUMPY"
#: The first bytes of a zip archive (``.npz``): a local file header, or an empty archive's end record.
ZIP_MAGICS = (b"PK\x03\x04", b"PK\x05\x06")


@dataclass(frozen=True)
class TextPoints:
    """The content of a text point file.

    Attributes
    ----------
    points : ndarray of shape (n, k)
    header : tuple of str or None
        The column names of a header line, when the file had one.
    header_line : int or None
        Its line number, counting from 1.
    """

    points: np.ndarray
    header: tuple[str, ...] | None = None
    header_line: int | None = None

    def note(self, path: str | Path) -> str | None:
        """A sentence saying that the header line was skipped (None without a header)."""
        if self.header is None:
            return None
        return (
            f"{Path(path).name}: line {self.header_line} was read as column names "
            f"({', '.join(self.header)}), not as a point."
        )


def _shown(line: str, limit: int = 40) -> str:
    return repr(line if len(line) <= limit else line[: limit - 1] + "…")


def _names(tokens: list[str]) -> tuple[str, ...] | None:
    """The column names of a header line, or None when some entry is not a name."""
    names = tuple(t.strip("\"'") for t in tokens)
    if names and all(_NAME.match(n) for n in names):
        return names
    return None


def read_text_points(path: str | Path) -> TextPoints:
    """Read a delimited text point file.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    TextPoints
        The rows as floats (shape (n, k), not yet checked for finiteness or
        k >= 2) and the header line, if any.

    Raises
    ------
    InputError
        A file that is not UTF-8, has no points, a line that is neither
        numbers nor (first line only) a header of column names, a header
        whose number of names differs from the number of columns, or rows of
        different lengths.  The message names the file and the line.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"Cannot read '{path}': it is not a UTF-8 text file.") from None
    except OSError as err:
        reason = (err.strerror or str(err)).rstrip(".")
        raise InputError(f"Cannot read '{path}': {reason}.") from None
    rows: list[list[float]] = []
    header: tuple[str, ...] | None = None
    header_line: int | None = None
    first = True
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        tokens = [t for t in _SPLIT.split(line) if t]
        values: list[float | None] = []
        for tok in tokens:
            try:
                values.append(float(tok))
            except ValueError:
                values.append(None)
        if first and all(v is None for v in values):
            first = False
            header = _names(tokens)
            if header is None:
                raise InputError(
                    f"Cannot read '{path}': line {lineno} ({_shown(line)}) is neither numbers "
                    "nor a header of column names."
                )
            header_line = lineno
            continue
        first = False
        if any(v is None for v in values):
            bad = tokens[values.index(None)]
            raise InputError(f"Cannot read '{path}': line {lineno} has the non-number {bad!r}.")
        if header is not None and not rows and len(values) != len(header):
            raise InputError(
                f"Cannot read '{path}': line {header_line} names {len(header)} columns "
                f"({', '.join(header)}) but line {lineno} has {len(values)} values."
            )
        if rows and len(values) != len(rows[0]):
            raise InputError(
                f"Cannot read '{path}': line {lineno} has {len(values)} values but earlier lines have {len(rows[0])}."
            )
        rows.append(values)  # type: ignore[arg-type]
    if not rows:
        raise InputError(f"Cannot read '{path}': the file contains no points.")
    return TextPoints(np.array(rows, dtype=float), header, header_line)


def check_signature(path: Path, kind: str) -> None:
    """Raise a one-line :class:`InputError` unless ``path`` starts like a ``.npy`` or ``.npz`` file.

    Parameters
    ----------
    path : Path
    kind : {"npy", "npz"}
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(8)
    except OSError as err:
        reason = (err.strerror or str(err)).rstrip(".")
        raise InputError(f"Cannot read '{path}': {reason}.") from None
    if kind == "npy" and not head.startswith(NPY_MAGIC):
        raise InputError(
            f"Cannot read '{path}': not a NumPy array file (a .npy file starts with "
            "the bytes \\x93NUMPY; this one does not)."
        )
    if kind == "npz" and not head.startswith(ZIP_MAGICS):
        raise InputError(f"Cannot read '{path}': not a NumPy .npz archive (it is not a zip file).")

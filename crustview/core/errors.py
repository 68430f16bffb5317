"""Exceptions raised by the reconstruction core.

Every message is one sentence that tells the user what is wrong and, where
possible, what to change.  The command line prints ``str(err)`` alone; the
viewer shows it in a message box.
"""

from __future__ import annotations


class CrustviewError(ValueError):
    """Base class of every error crustview reports to a user."""


class InputError(CrustviewError):
    """The point set or the parameters cannot be used (NaN, too few points, bad d ...)."""


class QhullFailure(CrustviewError):
    """Qhull could not triangulate the (prepared) points."""


class Cancelled(CrustviewError):
    """The caller asked the run to stop (``cancel.is_set()`` became true)."""


def check_cancel(cancel: object | None) -> None:
    """Raise :class:`Cancelled` when ``cancel`` (anything with ``is_set()``, e.g. a ``threading.Event``) is set."""
    if cancel is not None and cancel.is_set():
        raise Cancelled("reconstruction cancelled")

"""Output files: checked for writability before any work, written atomically with the user's umask.

Every file seispound writes (result HDF5, study store and journal, figures,
query CSV/JSON) goes through :func:`check_writable` before the computation
starts, so that an output path that cannot be written costs one line and no
work, and through :func:`atomic_output` when written, so that a failure leaves
nothing half-written and the finished file has the permissions any Unix tool
would give it (``0o666 & ~umask``; :func:`tempfile.mkstemp` alone gives 0600).
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from pathlib import Path

from .errors import InputError

__all__ = ["check_writable", "atomic_output", "default_file_mode"]

_REASONS = {
    errno.EROFS: "read-only file system",
    errno.EACCES: "permission denied",
    errno.EPERM: "permission denied",
    errno.ENOSPC: "no space left on the device",
    errno.EDQUOT: "disk quota exceeded",
    errno.ENOENT: "cannot create files in this folder",
    errno.ENOTDIR: "a part of the path is not a folder",
    errno.ENAMETOOLONG: "file name too long",
}


def default_file_mode() -> int:
    """Permission bits of a new regular file under the current umask (0o666 & ~umask)."""
    mask = os.umask(0)  # the only portable way to read the umask is to set it
    os.umask(mask)
    return 0o666 & ~mask


def _reason(exc: OSError) -> str:
    return _REASONS.get(exc.errno, exc.strerror or type(exc).__name__)


def check_writable(path, *, key: str = "output", suffixes=None) -> Path:
    """Check that ``path`` can be created or replaced, before any work is done.

    Creates and removes a probe file in the target folder, which is the only
    test that sees read-only mounts, virtual file systems (``/proc``) and
    permissions as the process actually has them (``os.access`` answers yes
    to root on a read-only mount's files).

    Parameters
    ----------
    path : str or path-like
        The output file.
    key : str
        The option or key that named it (``-o``, ``--output``), for the error.
    suffixes : sequence of str, optional
        Allowed suffixes (lower case, with the dot).

    Returns
    -------
    Path

    Raises
    ------
    InputError
        One line naming the path and why: "is a directory", "output folder does
        not exist", "read-only file system", "permission denied", ...
    """
    path = Path(path)
    if path.is_dir():
        raise InputError("is a directory; give a file name", file=path, key=key)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise InputError(f"must end in {', '.join(suffixes[:-1])} or {suffixes[-1]}" if len(suffixes) > 1
                         else f"must end in {suffixes[0]}", file=path, key=key)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.exists():
        raise InputError(f"output folder does not exist: {folder}", file=path, key=key)
    if not folder.is_dir():
        raise InputError(f"not a folder: {folder}", file=path, key=key)
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".probe", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write here: {_reason(exc)}", file=path, key=key) from None
    os.close(fd)
    os.unlink(probe)
    if path.exists() and not os.access(path, os.W_OK):
        raise InputError("cannot write here: permission denied (the file is read-only)", file=path, key=key)
    return path


@contextlib.contextmanager
def atomic_output(path, *, key: str = "output"):
    """Yield a temporary path next to ``path``; on success give it the umask's mode and rename it into place.

    On any exception the temporary file is removed and ``path`` is untouched.
    An OSError while creating the temporary file becomes a one-line InputError.

    Examples
    --------
    >>> with atomic_output("out.csv") as tmp:          # doctest: +SKIP
    ...     Path(tmp).write_text("a,b\\n")
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write here: {_reason(exc)}", file=path, key=key) from None
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, default_file_mode())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise

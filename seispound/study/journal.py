"""The study journal: an append-only file of finished runs, safe against a kill at any moment.

``STUDY.h5.journal`` sits next to the store while a study is in progress.
Each finished run is appended as one frame ``MAGIC | length | crc32 | payload``
(payload: the pickled result dict) in a single ``write``; a process killed
mid-append leaves at most one incomplete frame at the end, which the next
reader detects (short or failing its CRC) and cuts off.  The first frame holds
the study hash, so a journal is never resumed by a different study.

The journal is the source of truth until the study is complete; the HDF5
store is rebuilt from it (atomically) at snapshots and at the end.
"""

from __future__ import annotations

import os
import pickle
import struct
import zlib
from pathlib import Path

from ..errors import InputError

__all__ = ["Journal", "journal_path"]

_MAGIC = b"SPJ1"
_HEAD = struct.Struct("<4sQI")  # magic, payload length, crc32


def journal_path(store: Path) -> Path:
    return Path(str(store) + ".journal")


class Journal:
    """Append-only run journal for the store ``store`` of the study with hash ``study_hash``."""

    def __init__(self, store: Path, study_hash: str):
        self.path = journal_path(Path(store))
        self.study_hash = study_hash
        self.done: dict[int, int] = {}  # run index -> status
        self._fd = None

    # -- reading ---------------------------------------------------------------------
    def _frames(self):
        """(offset after frame, payload object) of every intact frame, in order."""
        with open(self.path, "rb") as fh:  # frame by frame: memory stays one run deep
            pos = 0
            while True:
                head = fh.read(_HEAD.size)
                if len(head) < _HEAD.size:
                    return
                magic, n, crc = _HEAD.unpack(head)
                if magic != _MAGIC:
                    return
                payload = fh.read(n)
                if len(payload) < n or zlib.crc32(payload) != crc:
                    return
                try:
                    obj = pickle.loads(payload)
                except Exception:  # a damaged frame: everything from here on is dropped
                    return
                pos += _HEAD.size + n
                yield pos, obj

    def records(self):
        """Every run result stored, in the order appended, first occurrence of each index only."""
        if not self.path.exists():
            return
        seen = set()
        for k, (_, obj) in enumerate(self._frames()):
            if k == 0:
                continue  # the header
            if obj["index"] not in seen:
                seen.add(obj["index"])
                yield obj

    def open(self) -> "Journal":
        """Open for appending: check the header, cut a torn last frame, index what is stored."""
        if self.path.exists():
            end = 0
            header = None
            for k, (pos, obj) in enumerate(self._frames()):
                if k == 0:
                    header = obj
                else:
                    self.done.setdefault(int(obj["index"]), int(obj["status"]))
                end = pos
            if header is None:
                end = 0  # not even a header: start over
            elif header.get("study_hash") != self.study_hash:
                raise InputError("the journal of this store belongs to another study (different model, "
                                 "records, axes or version); choose another output file or pass --overwrite",
                                 file=self.path, key="study_hash")
            with open(self.path, "r+b") as fh:
                fh.truncate(end)
        # mode 0o666: the umask decides, as for every file seispound writes
        self._fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o666)
        if os.fstat(self._fd).st_size == 0:
            self._append({"study_hash": self.study_hash})
        return self

    # -- writing ---------------------------------------------------------------------
    def _append(self, obj) -> None:
        payload = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
        frame = _HEAD.pack(_MAGIC, len(payload), zlib.crc32(payload)) + payload
        view = memoryview(frame)
        while view:  # one write in practice; loop only for a short write
            n = os.write(self._fd, view)
            view = view[n:]

    def append(self, result: dict) -> None:
        """Store one finished run (never twice: a second result for an index is ignored)."""
        idx = int(result["index"])
        if idx in self.done:
            return
        self._append(result)
        self.done[idx] = int(result["status"])

    def sync(self) -> None:
        if self._fd is not None:
            os.fsync(self._fd)

    def close(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def remove(self) -> None:
        self.close()
        self.path.unlink(missing_ok=True)

# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""Results folders: a new one never overwrites anything, a resumed one must hold the same
study, one command at a time writes in a folder (a lock), and every result file appears
whole or not at all (written to a temporary file, then renamed)."""

import errno
import fcntl
import json
import os
import tempfile
from contextlib import contextmanager
from datetime import datetime
from pathlib import Path

import numpy as np

LOCK = ".cgms.lock"


class FolderError(ValueError):
    """A results folder that cannot be used as asked (the message says why)."""


def default_folder(kind):
    """``results/<kind>/<date-time>``, numbered on when a command started in the same
    second already took it."""
    stem = Path("results") / kind / datetime.now().strftime("%Y%m%d-%H%M%S")
    path, n = stem, 1
    while path.exists():
        n += 1
        path = stem.with_name(f"{stem.name}-{n}")
    return path


def summary_path(folder):
    """A new summary table in ``folder``, named by the time of day; a run that ends within
    the same second as an earlier one (a resume of finished levels) gets the next free
    number, so no table of an earlier run is overwritten."""
    stem = f"summary-{datetime.now():%H%M%S}"
    path, n = Path(folder) / f"{stem}.csv", 1
    while path.exists():
        n += 1
        path = Path(folder) / f"{stem}-{n}.csv"
    return path


def _lock(folder):
    """An exclusive lock on ``folder`` held while the returned file stays open."""
    fh = open(folder / LOCK, "a")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        fh.close()
        raise FolderError(f"{folder} is in use by another cgms command; wait for it to end "
                          "or choose another --out") from None
    return fh


@contextmanager
def claim(out, kind, resume=False, resumable=True):
    """The results folder of one command, locked while the ``with`` block runs.

    New (``resume`` false): ``out`` (default ``results/<kind>/<date-time>``) is created; it
    may exist only as an empty folder. Resumed: ``out`` must be given and be a folder.
    ``resumable``: whether the command has ``--resume`` (the refusal of a folder in use
    offers it only then). FolderError says what is wrong; nothing is created then."""
    if resume and not out:
        raise FolderError("--resume continues the study in --out: give the folder with --out")
    out = Path(out) if out else default_folder(kind)
    if out.exists() and not out.is_dir():
        raise FolderError(f"--out {out} is a file, not a folder")
    if resume and not out.exists():
        raise FolderError(f"--resume: {out} does not exist (nothing to continue); leave out "
                          "--resume to start a new study there")
    if not resume and out.exists() and any(p.name != LOCK for p in out.iterdir()):
        raise FolderError(f"{out} exists and is not empty; choose another --out"
                          + (" (or --resume to continue an interrupted study there)"
                             if resumable else ""))
    try:
        out.mkdir(parents=True, exist_ok=True)
        fh = _lock(out)
    except OSError as err:
        raise FolderError(f"cannot write in {out}: {err.strerror or err}") from None
    try:
        if not resume and any(p.name != LOCK for p in out.iterdir()):   # lost a race
            raise FolderError(f"{out} is being filled by another cgms command; choose "
                              "another --out")
        yield out
    finally:
        fh.close()


def write_atomic(path, write, replace=True):
    """Create ``path`` whole or not at all: ``write(file object)`` fills a temporary file
    beside it, which is then renamed to ``path``. With ``replace`` false an existing
    ``path`` is kept (FileExistsError): the file is linked in, which never replaces."""
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), os.fspath(path))
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as err:   # named by the file asked for, not the temporary one
        raise OSError(err.errno, err.strerror, os.fspath(path)) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        if replace:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)
            except FileExistsError:
                raise
            except OSError:   # a file system without hard links: check, then rename
                if path.exists():
                    raise FileExistsError(path) from None
                os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)
    return path


def write_text(path, text, overwrite=False):
    """A new text file written whole or not at all; an existing one is kept
    (FileExistsError naming it) unless ``overwrite``."""
    try:
        return write_atomic(path, lambda fh: fh.write(text.encode()), replace=overwrite)
    except FileExistsError:
        raise FileExistsError(f"{os.fspath(path)} exists; pass overwrite=True to replace it") \
            from None


def write_json(path, obj):
    return write_atomic(path, lambda fh: fh.write((json.dumps(obj, indent=1) + "\n").encode()))


def write_npy(path, array):
    return write_atomic(path, lambda fh: np.save(fh, array))


def read_json(path):
    """A JSON result file; ValueError naming the file if it is not whole."""
    try:
        return json.loads(Path(path).read_text())
    except (ValueError, UnicodeDecodeError) as err:
        raise ValueError(f"{path} is damaged ({err}); delete it to recompute what it "
                         "held") from None


def read_npy(path):
    try:
        return np.load(path)
    except (ValueError, OSError, EOFError) as err:
        raise ValueError(f"{path} is damaged or missing ({err}); delete it and its .json "
                         "to recompute that level") from None


def same_setup(path, setup, kept=()):
    """Record ``setup`` (a JSON-able dict of what defines the results in a folder) in
    ``path``, or, if it is there, check that it is the same: FolderError naming the
    entries that differ (results of another setup must never be mixed). ``kept``: entries
    the record may hold besides the setup (what was done with it), left out of the check."""
    setup = json.loads(json.dumps(setup))   # as JSON will read it back
    if Path(path).exists():
        old = {k: v for k, v in read_json(path).items() if k not in kept}
        if old != setup:
            diff = sorted(k for k in set(old) | set(setup) if old.get(k) != setup.get(k))
            shown = "; ".join(f"{k}: {old.get(k)!r} there, {setup.get(k)!r} now" for k in diff)
            raise FolderError(f"{Path(path).parent} holds results of another setup ({shown}); "
                              "resume with the same options or choose another --out")
    else:
        write_json(path, setup)

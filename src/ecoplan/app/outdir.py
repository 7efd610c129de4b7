"""Report folders that never overwrite anyone's files silently, with a manifest.

Policy: a missing or empty folder is created and used.  A folder that ecoplan wrote
before (it holds :data:`MANIFEST`, listing ecoplan's files) is reused, and only the files
ecoplan listed there may be replaced.  Any other non-empty folder is refused unless
``force`` is true.  Files written by code that does not go through :meth:`OutDir.file`
(e.g. the diagnosis report) are claimed with :meth:`OutDir.recording`, which compares the
folder before and after instead of trusting modification times.

>>> slug("RRT* / energy")
'RRTstar-energy'
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from ecoplan.errors import InputError

__all__ = ["MANIFEST", "OutDir", "case_file_names", "prepare_out_dir", "slug"]

#: Name of the file listing what ecoplan wrote into a report folder.
MANIFEST = ".ecoplan-manifest.json"


def slug(name: str) -> str:
    """A file-name-safe version of a case name (``*`` reads as ``star``).

    Parameters
    ----------
    name : str
        Any name.

    Returns
    -------
    str
        At most 80 characters of ``[A-Za-z0-9._-]``, ``"case"`` if nothing is left.
    """
    s = re.sub(r"[^A-Za-z0-9._-]+", "-", name.replace("*", "star")).strip("-.")
    return s[:80] or "case"


def case_file_names(names: Sequence[str]) -> list[str]:
    """Names of the cases' CSV logs in a report folder (unique, file-name safe).

    Parameters
    ----------
    names : sequence of str
        Case names, in order.

    Returns
    -------
    list of str
        ``<slug>.csv`` per case; repeated slugs get ``-2``, ``-3``, ...

    Examples
    --------
    >>> case_file_names(["a b", "a-b", "c"])
    ['a-b.csv', 'a-b-2.csv', 'c.csv']
    """
    out: list[str] = []
    for name in names:
        base = s = slug(name)
        k = 2
        while s in out:
            s = f"{base}-{k}"
            k += 1
        out.append(s)
    return [f"{s}.csv" for s in out]


@dataclass
class OutDir:
    """A report folder that records what ecoplan writes into it.

    Attributes
    ----------
    path : Path
        The folder.
    written : list of Path
        Files written so far (relative names go to the manifest).
    """

    path: Path
    written: list[Path] = field(default_factory=list)

    def file(self, name: str) -> Path:
        """Path of a file to write (recorded in the manifest)."""
        p = self.path / name
        self.written.append(p)
        return p

    def claim(self, names: Sequence[str], *, force: bool = False) -> None:
        """Refuse (InputError) to replace a file ecoplan did not write, unless ``force``.

        Parameters
        ----------
        names : sequence of str
            File names about to be written into the folder.
        force : bool
            Allow replacing files ecoplan did not write.
        """
        _check_not_foreign(self, names, force)

    @contextmanager
    def recording(self) -> Iterator[None]:
        """Record the files created or changed inside the ``with`` block as ecoplan's.

        For writers that take a folder rather than :meth:`file` (the diagnosis report):
        the folder is listed before and after, and a file counts as written when it is
        new or its size or modification time changed.  Files that were there and did not
        change stay foreign.
        """
        before = _snapshot(self.path)
        yield
        after = _snapshot(self.path)
        self.written.extend(
            self.path / name for name, stamp in sorted(after.items()) if before.get(name) != stamp
        )

    def finish(self) -> list[Path]:
        """Write the manifest; return the files written.

        The manifest lists the files written now and those an earlier run listed that are
        still there, so a file ecoplan wrote stays ecoplan's when a later run skips it.
        """
        earlier = _manifest_files(self.path / MANIFEST) or set()
        kept = {name for name in earlier if (self.path / name).exists()}
        manifest = {
            "tool": "ecoplan",
            "written_utc": datetime.now(UTC).isoformat(timespec="seconds"),
            "files": sorted(kept | {p.name for p in self.written}),
        }
        (self.path / MANIFEST).write_text(json.dumps(manifest, indent=1) + "\n")
        return list(dict.fromkeys(self.written))


def prepare_out_dir(path: str | Path, *, force: bool = False) -> OutDir:
    """Create or reuse a report folder without overwriting anyone's files silently.

    Policy: a missing or empty folder is created and used.  A folder that ecoplan wrote
    before (it holds :data:`MANIFEST`) is reused, and only the files ecoplan listed there
    may be replaced.  Any other non-empty folder is refused unless ``force`` is true.

    Parameters
    ----------
    path : str or Path
        The folder (``--out``).
    force : bool
        Write into a non-empty folder that ecoplan did not create (``--force``).

    Returns
    -------
    OutDir
        The folder, ready for writing.

    Raises
    ------
    InputError
        The path is a file, or a non-empty foreign folder without ``force``.
    """
    p = Path(path)
    if p.exists() and not p.is_dir():
        raise InputError(f"--out {p}: exists and is not a folder")
    if p.is_dir() and not force:
        entries = {e.name for e in p.iterdir()}
        if entries:
            if _manifest_files(p / MANIFEST) is None:
                raise InputError(
                    f"--out {p}: folder exists and holds files ecoplan did not write; "
                    "choose another folder or pass --force"
                )
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"--out {p}: cannot create folder: {exc.strerror or exc}") from None
    return OutDir(p)


def _snapshot(folder: Path) -> dict[str, tuple[int, int]]:
    """``name -> (size, mtime_ns)`` of the regular files in ``folder`` (manifest excluded)."""
    out: dict[str, tuple[int, int]] = {}
    for p in folder.iterdir():
        if p.is_file() and p.name != MANIFEST:
            st = p.stat()
            out[p.name] = (st.st_size, st.st_mtime_ns)
    return out


def _manifest_files(path: Path) -> set[str] | None:
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(data, dict) or data.get("tool") != "ecoplan":
        return None
    files = data.get("files", [])
    return {str(f) for f in files} if isinstance(files, list) else None


def _check_not_foreign(out: OutDir, names: Sequence[str], force: bool) -> None:
    if force:
        return
    ours = _manifest_files(out.path / MANIFEST) or set()
    for name in names:
        if (out.path / name).exists() and name not in ours:
            raise InputError(
                f"--out {out.path}: would overwrite {name}, which ecoplan did not write; "
                "move it or pass --force"
            )

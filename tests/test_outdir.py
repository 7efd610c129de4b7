"""Report folders: the manifest names ecoplan's files; foreign files are never replaced silently."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from ecoplan.app.outdir import MANIFEST, prepare_out_dir
from ecoplan.errors import InputError


def test_recording_claims_new_and_changed_files_only(tmp_path: Path) -> None:
    folder = prepare_out_dir(tmp_path / "rep")
    (folder.path / "kept.txt").write_text("already here")
    (folder.path / "changed.txt").write_text("old")
    old = folder.path / "changed.txt"
    os.utime(old, ns=(1_000_000_000, 1_000_000_000))  # an old stamp, so a rewrite shows
    with folder.recording():
        (folder.path / "new.json").write_text("{}")
        old.write_text("new contents")
    files = folder.finish()
    assert sorted(p.name for p in files) == ["changed.txt", "new.json"]
    manifest = json.loads((folder.path / MANIFEST).read_text())
    assert manifest["files"] == ["changed.txt", "new.json"]


def test_foreign_files_are_refused_unless_forced(tmp_path: Path) -> None:
    target = tmp_path / "rep"
    target.mkdir()
    (target / "notes.md").write_text("mine")
    with pytest.raises(InputError, match="did not write"):
        prepare_out_dir(target)
    folder = prepare_out_dir(target, force=True)
    with pytest.raises(InputError, match=r"would overwrite notes\.md"):
        folder.claim(["notes.md"])
    folder.claim(["notes.md"], force=True)


def test_a_folder_ecoplan_wrote_is_reused_for_its_own_files(tmp_path: Path) -> None:
    folder = prepare_out_dir(tmp_path / "rep")
    folder.file("a.csv").write_text("x\n")
    folder.finish()
    again = prepare_out_dir(tmp_path / "rep")
    again.claim(["a.csv"])  # listed in the manifest: may be replaced
    (again.path / "b.csv").write_text("someone else's")
    with pytest.raises(InputError, match=r"would overwrite b\.csv"):
        again.claim(["b.csv"])


def test_a_file_an_earlier_run_wrote_stays_ecoplans(tmp_path: Path) -> None:
    first = prepare_out_dir(tmp_path / "rep")
    first.file("map.png").write_text("png")
    first.file("old.csv").write_text("x\n")
    first.finish()
    second = prepare_out_dir(tmp_path / "rep")
    second.file("map.png").write_text("png2")  # this run writes no old.csv
    second.finish()
    manifest = json.loads((second.path / MANIFEST).read_text())
    assert manifest["files"] == ["map.png", "old.csv"]
    (second.path / "old.csv").unlink()
    third = prepare_out_dir(tmp_path / "rep")
    third.file("map.png").write_text("png3")
    third.finish()
    assert json.loads((third.path / MANIFEST).read_text())["files"] == ["map.png"]

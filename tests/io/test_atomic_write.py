"""Atomic text and bytes output: replace in one step, no leftovers, OSError -> OutputError with the path."""

from __future__ import annotations

import os

import pytest

from trcopt.errors import TrcoptError
from trcopt.io.atomic import OutputError, write_bytes_atomic, write_text_atomic


def test_writes_and_replaces(tmp_path):
    p = tmp_path / "a.nc"
    write_text_atomic(p, "old\n")
    write_text_atomic(p, "N10 G0 X1\nN20 M30\n")
    assert p.read_text() == "N10 G0 X1\nN20 M30\n"
    assert os.listdir(tmp_path) == ["a.nc"]


def test_missing_folder_raises_output_error_with_path(tmp_path):
    p = tmp_path / "nope" / "a.nc"
    with pytest.raises(OutputError) as info:
        write_text_atomic(p, "x")
    assert isinstance(info.value, TrcoptError) and isinstance(info.value, OSError)
    assert info.value.path == str(p)
    assert str(p) in str(info.value)


def test_failure_during_replace_keeps_the_old_file(tmp_path, monkeypatch):
    p = tmp_path / "a.svg"
    p.write_text("complete old file")

    def boom(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OutputError, match="No space left"):
        write_text_atomic(p, "new")
    assert p.read_text() == "complete old file"
    assert os.listdir(tmp_path) == ["a.svg"]  # the temporary file was removed


def test_bytes_are_written_unchanged_and_replace(tmp_path):
    p = tmp_path / "a.png"
    write_bytes_atomic(p, b"old")
    data = bytes(range(256)) + b"\r\n\n"
    assert write_bytes_atomic(p, data) == p
    assert p.read_bytes() == data
    assert os.listdir(tmp_path) == ["a.png"]


def test_text_keeps_its_line_ends(tmp_path):
    p = tmp_path / "a.csv"
    write_text_atomic(p, "t_s,block\r\n0.0,N10\r\n")
    assert p.read_bytes() == b"t_s,block\r\n0.0,N10\r\n"


def test_bytes_failure_during_replace_keeps_the_old_file(tmp_path, monkeypatch):
    p = tmp_path / "a.png"
    p.write_bytes(b"complete old file")

    def boom(src, dst):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "replace", boom)
    with pytest.raises(OutputError, match="No space left") as info:
        write_bytes_atomic(p, b"new")
    assert info.value.path == str(p)
    assert p.read_bytes() == b"complete old file"
    assert os.listdir(tmp_path) == ["a.png"]


def test_ctrl_c_during_the_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    p = tmp_path / "feed.csv"
    p.write_text("complete old file")

    def interrupted(fd):
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_text_atomic(p, "t_s,s_mm\n0,0\n")
    assert p.read_text() == "complete old file"
    assert os.listdir(tmp_path) == ["feed.csv"]

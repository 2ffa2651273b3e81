"""A cache that cannot be written ($INERTIAPROOF_CACHE) is read where it can be and otherwise skipped, with one
warning on stderr; never a crash (issue 27).

The tests run as root, whom permissions do not stop: a read-only cache is a path through a regular file (mkdir
fails with ENOTDIR) or writes that fail (monkeypatched)."""

import pathlib

import pytest

from inertiaproof import cli
from inertiaproof.suite import paths


@pytest.fixture
def fresh_warning(monkeypatch):
    monkeypatch.setattr(paths, "_WARNED", [])


@pytest.fixture
def unmakeable_cache(tmp_path, monkeypatch, fresh_warning):
    blocker = tmp_path / "a-regular-file"
    blocker.write_text("not a folder")
    cache = blocker / "cache"
    monkeypatch.setenv("INERTIAPROOF_CACHE", str(cache))
    return cache


def warnings_in(err):
    return [line for line in err.splitlines() if "warning: the cache" in line]


def test_cache_dir_under_a_regular_file_warns_once_and_does_not_raise(unmakeable_cache, capsys):
    assert paths.cache_dir() == unmakeable_cache
    assert paths.cache_dir() == unmakeable_cache
    (line,) = warnings_in(capsys.readouterr().err)
    assert str(unmakeable_cache) in line and "INERTIAPROOF_CACHE" in line


def test_a_symbolic_check_runs_with_an_unmakeable_cache(unmakeable_cache, tmp_path, capsys):
    from inertiaproof.symbolic import derivations

    derivations.forget()  # derived again, so that the result is stored (and cannot be)
    code = cli.main(["run", "--only", "Prop1:symbolic", "--out", str(tmp_path / "out"), "--quiet"])
    out, err = capsys.readouterr()
    assert code == 0 and "HOLDS" in out and "crashed" not in out and "Traceback" not in err
    (line,) = warnings_in(err)
    assert str(unmakeable_cache) in line
    derivations.forget()


def test_a_read_only_cache_is_read_and_not_written(tmp_path, monkeypatch, capsys, fresh_warning):
    from inertiaproof.symbolic import cache

    monkeypatch.setenv("INERTIAPROOF_CACHE", str(tmp_path / "cache"))
    assert cache.store("before", 42) is not None  # written while it could be
    real = pathlib.Path.write_bytes

    def read_only(self, data):
        if str(self).startswith(str(tmp_path / "cache")):
            raise PermissionError(13, "Permission denied", str(self))
        return real(self, data)

    monkeypatch.setattr(pathlib.Path, "write_bytes", read_only)
    assert cache.store("after", 1) is None
    assert cache.store("again", 2) is None
    assert cache.load("before") == 42 and cache.load("after") is None
    assert not list((tmp_path / "cache" / "symbolic").glob("*.tmp"))
    (line,) = warnings_in(capsys.readouterr().err)
    assert "Permission denied" in line


def test_the_hypothesis_database_of_deep_hunts_tolerates_an_unmakeable_cache(unmakeable_cache, capsys):
    from hypothesis import given, strategies as st

    from inertiaproof.suite.hunt import hunt_settings
    from inertiaproof.suite.profiles import PROFILES

    profile = next(p for p in PROFILES.values() if not p.derandomize)
    chosen = hunt_settings(profile, max_examples=5)
    assert chosen.database is not None

    @chosen
    @given(st.integers())
    def holds(x):
        assert x == x

    holds()
    assert len(warnings_in(capsys.readouterr().err)) == 1

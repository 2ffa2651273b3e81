"""``pytest --inertiaproof-audit PATH``: every robot file and link under PATH as a test item.

Registered as a pytest plugin (entry point ``pytest11``), so it is active
wherever inertiaproof is installed and does nothing without the option. Per
file under each PATH (a URDF or MJCF file, or a folder searched as
``inertiaproof audit`` searches it): one item per link and per body of
several links, passing when it is consistent, failing with the audit's
reason (and the suggested repair) when it is not; a link that is not judged
(a massless frame, a link that does not move) is skipped with the reason;
a file that cannot be read is one failing item. Chains are not bounded
(``--bounds none``): the items are about the inertias as written.
"""

from __future__ import annotations

from pathlib import Path

import pytest

__all__ = ["AuditFile", "AuditItem", "pytest_addoption", "pytest_collection_modifyitems"]


def pytest_addoption(parser):
    group = parser.getgroup("inertiaproof")
    group.addoption("--inertiaproof-audit", action="append", default=[], metavar="PATH",
                    help="audit the URDF/MJCF files under PATH: one test item per file and link (repeatable)")
    group.addoption("--inertiaproof-floating-base", action="store_true",
                    help="the robots' roots move (legged robots, humanoids): judge their links too")


def pytest_collection_modifyitems(session, config, items):
    for path in config.getoption("inertiaproof_audit"):
        items.extend(AuditFile.from_parent(session, path=Path(path).resolve()).collect())


class AuditError(Exception):
    pass


class AuditFile(pytest.File):
    """The files under one PATH, audited once at collection."""

    def collect(self):
        from .api import audit_urdf  # loaded with every pytest session: the numerical stack only when asked for

        audit = audit_urdf(self.path, bounds="none",
                           floating_base=self.config.getoption("inertiaproof_floating_base"))
        for path, f in audit.document["files"].items():
            prefix = f"{Path(path).relative_to(self.path).as_posix()}::" if self.path.is_dir() else ""
            if f["status"] != "ok":
                yield AuditItem.from_parent(self, name=f"{prefix}read", outcome=("fail", f["error"]))
                continue
            for name, link in f["links"].items():
                yield AuditItem.from_parent(self, name=f"{prefix}{name}", outcome=_link_outcome(link))
            for name, body in f["bodies"].items():
                if body["judged"] and len(body["links"]) > 1:
                    outcome = ("pass", "") if body["verdict"] == "consistent" else \
                        ("fail", f"body {name} (links {', '.join(body['links'])}): {body['verdict']}: {body['reason']}")
                    yield AuditItem.from_parent(self, name=f"{prefix}body {name}", outcome=outcome)


def _link_outcome(link):
    if link["massless_frame"]:
        return "skip", "a massless frame, not a body: not judged"
    if not link["moving"]:
        return "skip", f"{link['role']} link that does not move: not judged ({link['verdict']})"
    if link["verdict"] == "consistent":
        return "pass", ""
    repair = link["repair"] or {}
    written = repair.get("written")
    fix = (" -- suggested: " + " ".join(f'{k}="{v}"' for k, v in written.items())) if written else \
        (f" -- {repair['note']}" if repair.get("note") else "")
    signs = "".join(f"; {s['text']}" for s in link["signs"])
    return "fail", f"{link['verdict']}: {link['reason']}{signs}{fix}"


class AuditItem(pytest.Item):
    def __init__(self, *, outcome, **kwargs):
        super().__init__(**kwargs)
        self.outcome = outcome

    def runtest(self):
        kind, text = self.outcome
        if kind == "skip":
            pytest.skip(f"{self.name}: {text}")
        if kind == "fail":
            raise AuditError(text)

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, AuditError):
            return str(excinfo.value)
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, None, f"inertiaproof audit: {self.name}"

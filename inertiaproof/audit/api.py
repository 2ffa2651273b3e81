"""The audit from Python and in notebooks: ``inertiaproof.audit_urdf(path)``.

>>> import inertiaproof as ip                                  # doctest: +SKIP
>>> audit = ip.audit_urdf("robot.urdf")                        # doctest: +SKIP
>>> pandas.DataFrame(audit.to_records())                       # doctest: +SKIP

``audit.document`` is the JSON document of ``inertiaproof audit --json``
(schema ``inertiaproof.audit/1``); in Jupyter the object shows itself as a
table of links (``_repr_html_``).
"""

from __future__ import annotations

import html
import time

import numpy as np

from inertiaproof.suite.environment import versions
from inertiaproof.suite.profiles import PROFILES

from .document import audit_paths, document
from .repair import DEFAULT_SLACK

__all__ = ["Audit", "audit_urdf", "RECORD_FIELDS"]

RECORD_FIELDS = (
    "file", "robot", "format", "link", "role", "moving", "judged", "source", "line", "verdict", "reason",
    "triangle_slack_rel", "lambda_min_rel", "mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "iyz", "ixz", "signs",
    "mujoco", "drake", "pybullet", "gazebo", "repair",
)


class Audit:
    """One audit: ``document`` (a dict), ``to_records()`` and an HTML table for notebooks."""

    def __init__(self, document):
        self.document = document

    @property
    def exit_status(self):
        return self.document["summary"]["exit_status"]

    @property
    def consistent(self):
        """Every moving link and body of every file is consistent and every file was read."""
        return self.exit_status == 0

    def to_records(self):
        """One flat dict per link of every readable file (keys: ``RECORD_FIELDS``), for ``pandas.DataFrame``.

        ``verdict`` is the verdict of the numbers as written; only the ``judged`` links (moving, with mass or
        inertia) count: count verdicts over those, not over joint frames, massless frames or fixed bases."""
        out = []
        for path, f in self.document["files"].items():
            if f["status"] != "ok":
                continue
            for name, link in f["links"].items():
                written = link["inertial"] or {}
                com = written.get("com", [None] * 3)
                six = written.get("inertia", {})
                engines = link["engines"] or {}
                repair = link["repair"] or {}
                out.append({
                    "file": path, "robot": f["robot"], "format": f["format"], "link": name, "role": link["role"],
                    "moving": link["moving"], "judged": link["moving"] and not link["massless_frame"],
                    "source": link["source"],
                    "line": (link["location"] or {}).get("startLine"), "verdict": link["verdict"],
                    "reason": link["reason"], "triangle_slack_rel": link["triangle_slack_rel"],
                    "lambda_min_rel": link["lambda_min_rel"], "mass": written.get("mass"),
                    "com_x": com[0], "com_y": com[1], "com_z": com[2],
                    **{k: six.get(k) for k in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")},
                    "signs": ", ".join(s["sign"] for s in link["signs"]),
                    **{k: (engines.get(k) or {}).get("action") for k in ("mujoco", "drake", "pybullet", "gazebo")},
                    "repair": " ".join(f'{k}="{v}"' for k, v in (repair.get("written") or {}).items()) or None,
                })
        return out

    def _repr_html_(self):
        summary = self.document["summary"]
        head = (f"<p><b>inertiaproof audit</b>: {summary['files']} file(s), {summary['files_consistent']} consistent, "
                f"{summary['files_not_consistent']} not consistent, {summary['unreadable']} unreadable</p>")
        errors = "".join(f"<p>{html.escape(path)}: {html.escape(f['error'])}</p>"
                         for path, f in self.document["files"].items() if f["status"] != "ok")
        columns = ("file", "link", "role", "verdict", "mujoco", "drake", "pybullet", "gazebo", "signs", "repair",
                   "reason")
        rows = "".join(
            "<tr>" + "".join(f"<td>{html.escape('' if r[c] is None else str(r[c]))}</td>" for c in columns) + "</tr>"
            for r in self.to_records())
        table = ("<table><thead><tr>" + "".join(f"<th>{c}</th>" for c in columns) + "</tr></thead><tbody>"
                 + rows + "</tbody></table>")
        return head + errors + table

    def __repr__(self):
        s = self.document["summary"]
        return f"<Audit: {s['files']} file(s), exit status {s['exit_status']}>"


def audit_urdf(path, *, profile="ci", bounds="arms", floating_base=False, slack=DEFAULT_SLACK, seed=0,
               xacro_args=None):
    """The audit of a URDF, MJCF or xacro file, or of every URDF and MJCF file in a folder, as an :class:`Audit`.

    The options are those of ``inertiaproof audit`` (``xacro_args``: {name: value}, its ``--xacro-arg``); a file
    that cannot be read is an entry with ``status: error`` (and ``exit_status`` 2), not an exception.
    """
    budget = PROFILES[profile]
    start = time.perf_counter()
    extra = {"xacro_args": dict(xacro_args)} if xacro_args else {}
    samples, rounds = budget.audit_budget(bounds)
    with np.errstate(all="ignore"):
        files = audit_paths([path], samples=samples, rounds=rounds, bounds=bounds, **budget.audit_chains(bounds),
                            floating_base=floating_base, slack=slack, seed=seed, **extra)
    return Audit(document(files, profile=profile, seed=seed, bounds=bounds, floating_base=floating_base, slack=slack,
                          runtime_s=time.perf_counter() - start, versions=versions("yourdfpy", "mujoco")))

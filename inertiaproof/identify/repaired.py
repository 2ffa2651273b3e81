"""A copy of a URDF with the identified inertials, the rest of the file character for character.

Each body is a group of links (:mod:`inertiaproof.audit.kinematic_tree`); its identified Phi is the group's sum in
the anchor link's frame. The copy changes only the anchor link's ``<inertial>``: it gets the anchor's own Phi plus
the body's change (identified minus the file's), so the group's sum is the identified Phi and the links fixed to it
keep what the file writes (a finger still carries its own mass when it moves). The new element is the Phi in the
anchor's frame written as URDF writes it: mass, the CoM as ``<origin xyz>`` (rpy 0) and the inertia about the CoM
in the link's axes, 17 significant digits. The edit replaces the element's markup (its span,
:func:`inertiaproof.audit.locate.element_spans`) as ``audit --write-repaired`` does (:func:`.rewrite.apply`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from lxml import etree

from inertiaproof.audit.locate import decode, element_spans
from inertiaproof.audit.rewrite import apply
from inertiaproof.errors import InputError
from inertiaproof.model.consistency import physical_consistency
from inertiaproof.model.inertia import center_of_mass, inertia_com

__all__ = ["inertial_text", "repaired_urdf"]


def _num(x):
    return repr(float(x))


def inertial_text(phi, indent=""):
    """The ``<inertial>`` element of Phi (in the link's frame)."""
    c = center_of_mass(phi)
    i = inertia_com(phi)
    inertia = " ".join(f'{n}="{_num(i[a, b])}"' for n, (a, b) in
                       (("ixx", (0, 0)), ("ixy", (0, 1)), ("ixz", (0, 2)), ("iyy", (1, 1)), ("iyz", (1, 2)),
                        ("izz", (2, 2))))
    return (f'<inertial>\n{indent}  <origin xyz="{" ".join(map(_num, c))}" rpy="0 0 0"/>\n{indent}  <mass '
            f'value="{_num(phi[0])}"/>\n{indent}  <inertia {inertia}/>\n{indent}</inertial>')


def repaired_urdf(robot, theta):
    """(text, notes) of the copy of ``robot``'s URDF with bodies' Phi ``theta`` (N, 10); notes name anchors whose
    own written Phi is not consistent after the change (the group's sum may still be)."""
    source = robot.robot
    if source is None or source.format != "urdf":
        raise InputError(f"{robot.name}: a repaired copy is written for URDF files only")
    path = Path(source.path)
    text, _ = decode(path.read_bytes())
    root = etree.fromstring(text.encode("utf-8", errors="surrogateescape"))
    spans = element_spans(text, root)
    phis = dict(zip([link.name for link in source.links], source.link_phis()))
    changes, notes = [], []
    for group, phi, old in zip(robot.groups, np.asarray(theta, dtype=float), robot.theta):
        anchor = group.anchor
        new = phis[anchor] + (phi - old)
        element = root.find(f"link[@name='{anchor}']")
        if element is None:
            notes.append(f"{anchor}: no <link> element found; left as written")
            continue
        verdict = physical_consistency(new[None]).labels[0]
        if verdict != "consistent":
            notes.append(f"{anchor}: its own inertial is {verdict} after the change (the body's sum is what was "
                         "identified)")
        inertial = element.find("inertial")
        target = inertial if inertial is not None else element
        span = spans.get(target)
        if span is None or span.start is None:
            notes.append(f"{anchor}: its element could not be located in the text; left as written")
            continue
        line_start = text.rfind("\n", 0, span.start) + 1
        indent = text[line_start:span.start] if text[line_start:span.start].isspace() else ""
        if inertial is not None:
            changes.append((span.start, span.end, inertial_text(new, indent)))
        else:
            close = text.find(">", span.start)
            if text[close - 1] == "/":
                changes.append((span.start, span.end, text[span.start:close - 1].rstrip() + ">\n" + indent + "  "
                                + inertial_text(new, indent + "  ") + "\n" + indent + "</link>"))
            else:
                changes.append((close + 1, close + 1, "\n" + indent + "  " + inertial_text(new, indent + "  ")))
    return apply(text, changes), notes

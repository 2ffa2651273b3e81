"""Mirror twins: left/right links placed mirrored across a plane of the robot must have mirrored inertials (mass
equal, centre mirrored, I' = S I S in the base frame at q = 0); a mismatch is a warning naming both links and the
entries, in text, JSON, SARIF and GitHub annotations (:mod:`inertiaproof.audit.mirror_twins`)."""

import json

import pytest
from urdf_samples import inertial, joint, link, robot, write

from inertiaproof import cli
from inertiaproof.audit.mirror_twins import side_templates


def _legs(right_ixy=-0.002, right_xyz="0.02 -0.01 -0.1", right_joint="0 -0.1 0", left="left_leg",
          right="right_leg"):
    """A base with a left leg at y = +0.1 and a right one at y = right_joint; the left leg's ixy is 0.002, so its
    mirror across y = 0 has ixy -0.002 (and iyz flips, ixz stays)."""
    return robot(
        link("base", inertial(5.0, ixx=0.1, iyy=0.1, izz=0.1)),
        link(left, inertial(1.0, "0.02 0.01 -0.1", ixx=0.01, iyy=0.02, izz=0.025, ixy=0.002, iyz=0.001,
                            ixz=0.0015)),
        link(right, inertial(1.0, right_xyz, ixx=0.01, iyy=0.02, izz=0.025, ixy=right_ixy, iyz=-0.001,
                             ixz=0.0015)),
        joint("jl", "base", left, xyz="0 0.1 0", axis="0 1 0"),
        joint("jr", "base", right, xyz=right_joint, axis="0 1 0"))


def _audit(capsys, path, *argv):
    code = cli.main(["audit", "--bounds", "none", *argv, str(path)])
    return code, capsys.readouterr().out


def _twins(capsys, path):
    code, out = _audit(capsys, path, "--json")
    doc = json.loads(out)
    return code, doc, next(iter(doc["files"].values()))["mirror_twins"]


@pytest.mark.parametrize("name, expected", [
    ("left_hip", [("\0_hip", "left")]), ("RightFoot", [("\0Foot", "right")]), ("l_hip", [("\0_hip", "left")]),
    ("hip_R", [("hip_\0", "right")]), ("arm-L-1", [("arm-\0-1", "left")]), ("FL_hip", []), ("lower_leg", []),
    ("wheel", []),
])
def test_side_markers(name, expected):
    assert side_templates(name) == expected


def test_an_exact_mirrored_pair_is_not_flagged(tmp_path, capsys):
    code, doc, twins = _twins(capsys, write(tmp_path, _legs()))
    assert code == 0
    assert [(p["left"], p["right"], p["plane"], p["matches"]) for p in twins["pairs"]] == \
        [("left_leg", "right_leg", "y = 0", True)]
    assert twins["mismatches"] == 0
    assert not [f for f in doc["findings"] if f["rule"] == "mirror-twin-mismatch"]
    assert doc["summary"]["mirror_twins"] == {"pairs": 1, "mismatches": 0}


def test_a_flipped_product_of_inertia_is_a_warning_naming_the_entry(tmp_path, capsys):
    path = write(tmp_path, _legs(right_ixy=0.002))
    code, doc, twins = _twins(capsys, path)
    assert code == 0  # soft: a warning, not counted in the exit status
    (pair,) = twins["pairs"]
    assert not pair["matches"]
    assert [(d["entry"], d["left"], d["right"], d["expected"]) for d in pair["differences"]] == \
        [("ixy", 0.002, 0.002, -0.002)]
    assert "'left_leg'" in pair["message"] and "'right_leg'" in pair["message"]
    assert "ixy: 0.002 vs 0.002 expected -0.002" in pair["message"]
    (found,) = [f for f in doc["findings"] if f["rule"] == "mirror-twin-mismatch"]
    assert found["level"] == "warning" and found["subject"] == "links left_leg right_leg"
    assert doc["summary"]["mirror_twins"] == {"pairs": 1, "mismatches": 1}

    code, text = _audit(capsys, path)
    assert "mirror  links 'left_leg' and 'right_leg'" in text and "ixy: 0.002 vs 0.002 expected -0.002" in text
    assert "mirror pairs: 1, not mirrored: 1" in text

    sarif = tmp_path / "audit.sarif"
    _audit(capsys, path, "--sarif", str(sarif))
    run = json.loads(sarif.read_text())["runs"][0]
    (result,) = [r for r in run["results"] if r["ruleId"] == "mirror-twin-mismatch"]
    assert result["level"] == "warning" and "ixy: 0.002 vs 0.002" in result["message"]["text"]
    assert run["tool"]["driver"]["rules"][result["ruleIndex"]]["id"] == "mirror-twin-mismatch"
    assert result["locations"][0]["physicalLocation"]["region"]["startLine"] == 5  # the right leg's <inertia>

    code, out = _audit(capsys, path, "--github")
    (line,) = [x for x in out.splitlines() if "mirror-twin-mismatch" in x]
    assert line.startswith("::warning ") and "line=5" in line and "ixy: 0.002 vs 0.002 expected -0.002" in line


def test_mass_and_centre_mismatches_are_named(tmp_path, capsys):
    text = _legs(right_xyz="0.02 -0.01 -0.12").replace('<mass value="1.0"/>', '<mass value="1.2"/>', 2)
    text = text.replace('<mass value="1.2"/>', '<mass value="1.0"/>', 1)  # the left leg back to 1 kg
    _, _, twins = _twins(capsys, write(tmp_path, text))
    (pair,) = twins["pairs"]
    assert [d["entry"] for d in pair["differences"]][:2] == ["mass", "com z"]


def test_a_left_right_pair_not_placed_mirrored_is_not_a_pair(tmp_path, capsys):
    for k, placed in enumerate(["0 0.1 0", "0 -0.2 0", "0.1 -0.1 0"]):  # same side; not the mirror; off in x
        _, doc, twins = _twins(capsys, write(tmp_path, _legs(right_ixy=0.002, right_joint=placed), f"r{k}.urdf"))
        assert twins == {"pairs": [], "mismatches": 0}
        assert not [f for f in doc["findings"] if f["rule"] == "mirror-twin-mismatch"]


def test_token_markers_and_a_turned_right_frame(tmp_path, capsys):
    """``l_`` / ``r_`` names; the right link's frame turned by pi about z (its x and y flipped): compared in the
    base frame, the same body needs ixy unflipped and iyz, ixz flipped in its own frame."""
    text = robot(
        link("base", inertial(5.0, ixx=0.1, iyy=0.1, izz=0.1)),
        link("l_arm", inertial(1.0, "0.02 0.01 -0.1", ixx=0.01, iyy=0.02, izz=0.025, ixy=0.002, iyz=0.001,
                               ixz=0.0015)),
        # base-frame mirror: c = (0.02, -0.01, -0.1), ixy -0.002, iyz -0.001, ixz 0.0015; in a frame turned by
        # pi about z: c = (-0.02, 0.01, -0.1), ixy -0.002, iyz 0.001, ixz -0.0015
        link("r_arm", inertial(1.0, "-0.02 0.01 -0.1", ixx=0.01, iyy=0.02, izz=0.025, ixy=-0.002, iyz=0.001,
                               ixz=-0.0015)),
        joint("jl", "base", "l_arm", xyz="0.05 0.2 0.3", axis="0 1 0"),
        joint("jr", "base", "r_arm", xyz="0.05 -0.2 0.3", rpy="0 0 3.141592653589793", axis="0 1 0"))
    _, _, twins = _twins(capsys, write(tmp_path, text))
    (pair,) = twins["pairs"]
    assert (pair["left"], pair["right"], pair["matches"]) == ("l_arm", "r_arm", True), pair["differences"]

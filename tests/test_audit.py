"""The audit: signs of authoring mistakes, the convex repair, singularity, bounds hook, CLI contract, real robots."""

import io
import json
import time
import warnings
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from urdf_samples import inertial, joint, link, robot, robots_folder, two_link_arm, write

from inertiaproof import cli
from inertiaproof.audit.document import audit_paths, chain_bounds, is_serial_arm
from inertiaproof.audit.kinematic_tree import kinematic_tree
from inertiaproof.audit.mistakes import diagnose
from inertiaproof.audit.repair import nearest_consistent_inertia
from inertiaproof.audit.urdf import read_urdf
from inertiaproof.bounds.configuration import REPROVABLE
from inertiaproof.bounds.singular import singularity
from inertiaproof.dynamics.terms import mass_matrix
from inertiaproof.model.consistency import CONSISTENT, DEGENERATE, INCONSISTENT, LABELS, physical_consistency
from inertiaproof.model.inertia import pack, rotation_rpy, skew
from inertiaproof.suite.profiles import PROFILES

CI = dict(samples=PROFILES["ci"].audit_samples, rounds=PROFILES["ci"].audit_rounds)
SWEEP = dict(samples=PROFILES["ci"].audit_samples, rounds=2)  # dozens of chains: below PIVOT_MIN_ROUNDS, no ladders
ALLEGRO_TIP = np.array([[4.701248e-06, 1.255968e-06, 1.2936e-06],
                        [1.255968e-06, 3.649312e-06, 1.7622e-06],
                        [1.2936e-06, 1.7622e-06, 4.701248e-06]])


def _verdict(mass, inertia):
    return physical_consistency(pack(mass, np.zeros(3), inertia)).verdict.item()


def _signs(mass, inertia, offset=(0.0, 0.0, 0.0)):
    inertia = np.asarray(inertia, dtype=float)
    found, tested = diagnose(np.array([mass]), inertia[None], np.array([offset], dtype=float),
                             np.array([_verdict(mass, inertia)]))
    return {s["sign"]: s for s in found[0]}, tested[0]


# -- signs of authoring mistakes ------------------------------------------------

def test_power_of_ten_slip_is_found_and_ranked():
    signs, tested = _signs(0.05, np.diag([0.001, 0.001, 0.01]))  # PR2's sensor_mount_link
    assert "power_of_ten" in tested
    first = signs["power_of_ten"]["fixes"][0]
    assert (first["entry"], first["factor"]) == ("izz", 0.1)
    for fix in signs["power_of_ten"]["fixes"]:
        assert abs(np.log10(fix["factor"])) >= 1


def test_inertia_shifted_away_from_the_com_is_recognised():
    true = rotation_rpy([0.2, 0.1, -0.3]) @ np.diag([0.02, 0.03, 0.04]) @ rotation_rpy([0.2, 0.1, -0.3]).T
    d, m = np.array([0.12, 0.05, 0.0]), 2.0
    written = true - m * skew(d).T @ skew(d)
    assert _verdict(m, written) == INCONSISTENT
    signs, _ = _signs(m, written, d)
    fixed = signs["parallel_axis"]["inertia"]
    assert np.allclose([fixed["ixx"], fixed["iyy"], fixed["izz"], fixed["ixy"]], [true[0, 0], true[1, 1], true[2, 2], true[0, 1]])


def test_products_of_inertia_sign_convention_on_the_allegro_fingertip():
    assert _verdict(0.0096, ALLEGRO_TIP) == INCONSISTENT
    signs, _ = _signs(0.0096, ALLEGRO_TIP)
    assert "products_sign" in signs and signs["products_sign"]["inertia"]["ixy"] == -ALLEGRO_TIP[0, 1]


def test_patterns():
    assert "all_entries_equal" in _signs(1e-6, np.full((3, 3), 1e-6))[0]
    assert "massless_with_inertia" in _signs(0.0, np.eye(3) * 1e-3)[0]
    assert "negative_mass" in _signs(-1.0, np.eye(3))[0]
    signs, tested = _signs(0.5, np.zeros((3, 3)))
    assert "point_mass" in signs and tested == []  # degenerate: nothing to explain
    assert "negligible_inertia" in _signs(0.526, np.diag([-5.42101e-20, -5.42101e-20, 0.0]))[0]


def test_a_consistent_link_shows_no_sign_and_no_hypothesis():
    signs, tested = _signs(1.0, np.diag([0.01, 0.02, 0.025]), (0.1, 0.0, 0.0))
    assert signs == {} and tested == []


def test_an_unexplained_inconsistency_is_tested_but_shows_no_fix():
    signs, tested = _signs(1.0, np.diag([-1.0, -2.0, -3.0]))
    assert set(tested) == {"parallel_axis", "power_of_ten", "products_sign"} and signs == {}


# -- the convex repair -------------------------------------------------------------

def _projection_oracle(w, slack):
    """The nearest point of {x_i <= (1 - slack)/2 sum(x)} to w, by enumerating active sets (closed form in eigenvalues)."""
    a = np.eye(3) - 0.5 * (1 - slack)
    best = None
    for mask in range(8):
        rows = a[[i for i in range(3) if mask >> i & 1]]
        lam = np.linalg.solve(rows @ rows.T, rows @ w) if len(rows) else np.zeros(0)
        x = w - rows.T @ lam
        if np.all(lam >= -1e-12) and np.all(a @ x <= 1e-12 * np.abs(w).max()):
            if best is None or np.linalg.norm(x - w) < np.linalg.norm(best - w):
                best = x
    return best


def test_repair_is_the_nearest_consistent_inertia():
    rng = np.random.default_rng(3)
    for _ in range(20):
        rot = rotation_rpy(rng.normal(size=3))
        moments = rng.uniform(0.1, 1.0, 3) * 10.0 ** rng.uniform(-6, 0)
        k = rng.integers(3)
        moments[k] = (moments.sum() - moments[k]) * rng.uniform(1.01, 3)  # break the triangle inequality
        w = rot @ np.diag(moments) @ rot.T
        assert _verdict(1.0, w) == INCONSISTENT
        r = nearest_consistent_inertia(1.0, w, slack=1e-3)
        expected = rot @ np.diag(_projection_oracle(moments, 1e-3)) @ rot.T
        assert np.allclose(r.inertia, expected, rtol=1e-6, atol=1e-7 * np.linalg.norm(w))
        assert _verdict(1.0, r.inertia) == CONSISTENT and r.triangle_slack >= 1e-3 * (1 - 1e-6)
        assert r.change_frobenius_rel == pytest.approx(np.linalg.norm(expected - w) / np.linalg.norm(w), rel=1e-5)


def test_repair_declines_where_no_nearest_inertia_exists():
    assert nearest_consistent_inertia(1.0, np.zeros((3, 3))).inertia is None  # point mass
    assert nearest_consistent_inertia(0.526, np.diag([-5.4e-20, -5.4e-20, 0.0])).inertia is None  # rounding noise
    assert nearest_consistent_inertia(0.0, np.eye(3)).inertia is None  # massless
    assert nearest_consistent_inertia(1.0, -np.eye(3)).inertia is None  # shrinks to a point


# -- singularity and the bounds hook --------------------------------------------

def _chain(tmp_path, second):
    (sc,) = kinematic_tree(read_urdf(write(tmp_path, two_link_arm(second=second)))).chains
    codes = physical_consistency(sc.theta).verdict
    return sc, codes


def test_consistent_bodies_never_give_a_singular_mass_matrix(tmp_path):
    sc, codes = _chain(tmp_path, None)
    out = singularity(sc.chain, sc.theta, codes, ["l1", "l2"], chain_bounds(sc.chain, sc.theta, **CI))
    assert out["verdict"] == "never"


def test_massless_last_body_makes_m_singular_everywhere(tmp_path):
    sc, codes = _chain(tmp_path, "")
    out = singularity(sc.chain, sc.theta, codes, ["l1", "l2"])
    assert out["verdict"] == "everywhere" and out["rank_at_most"]["value"] == 1
    q = np.random.default_rng(0).uniform(-1.5, 1.5, (50, 2))
    assert np.all(mass_matrix(sc.chain.body_jacobian(q), sc.theta)[:, :, 1] == 0)


def test_negative_mass_body_is_caught_as_an_indefinite_mass_matrix(tmp_path):
    sc, codes = _chain(tmp_path, inertial(-0.9, "0.2 0 0", "0 0 0", 0.001, 0.01, 0.01))
    bounds = chain_bounds(sc.chain, sc.theta, **CI)
    out = singularity(sc.chain, sc.theta, codes, ["l1", "l2"], bounds)
    assert out["verdict"] == "indefinite" and bounds["lambda_min"]["value"] < 0
    m = mass_matrix(sc.chain.body_jacobian(np.array(out["at_q"])), sc.theta)
    assert np.linalg.eigvalsh(m)[0] < 0


def test_a_certified_lower_bound_decides_where_the_structure_cannot(tmp_path):
    sc, codes = _chain(tmp_path, inertial(0.5, "0.2 0 0", "0 0 0", 0.0, 0.0, 0.0))
    assert codes[1] == DEGENERATE
    certified = {"lambda_min": {"value": 1e-3, "kind": "lower_bound"}, "resolution": {"value": 1e-15}}
    assert singularity(sc.chain, sc.theta, codes, ["l1", "l2"], certified)["verdict"] == "never"
    assert singularity(sc.chain, sc.theta, codes, ["l1", "l2"])["verdict"] == "not_excluded"


def test_chain_bounds_bracket_the_eigenvalues_and_carry_both_alphas(tmp_path):
    text = robot(link("base"), link("disc", inertial(2.0, "0 0 0", "0 0 0", 0.3, 0.3, 0.5)), joint("j", "base", "disc"))
    (sc,) = kinematic_tree(read_urdf(write(tmp_path, text))).chains
    b = chain_bounds(sc.chain, sc.theta, **CI)
    # M(q) = I_zz = 0.5 for every q: the certified sides meet the sampled ones, as near as reported brackets go
    assert b["lambda_min"]["kind"] == "lower_bound" and b["lambda_min"]["value"] == pytest.approx(0.5 / REPROVABLE)
    assert b["lambda_max"]["kind"] == "sampled" and "lower estimate of the sup" in b["lambda_max"]["note"]
    assert b["inf_lambda_min_certified"]["value"] <= 0.5 <= b["sup_lambda_max_certified"]["value"]
    assert b["inf_lambda_min_sampled"]["value"] == pytest.approx(0.5, rel=1e-12)
    assert b["sup_lambda_max_certified"]["value"] == pytest.approx(0.5 * REPROVABLE)
    assert b["alpha1_paper_lower"]["value"] <= b["alpha1_paper_upper"]["value"]
    assert b["alpha2_paper_lower"]["value"] <= b["alpha2_paper_upper"]["value"]
    assert b["alpha1_certified"]["kind"] == b["alpha2_certified"]["kind"] == "certified_constant"
    assert b["alpha1_certified"]["value"] <= 0.5 + 1e-9 <= b["alpha2_certified"]["value"] + 2e-9


# -- the command ---------------------------------------------------------------------

def _run(capsys, *argv):
    code = cli.main(["audit", *map(str, argv)])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_exit_0_when_every_moving_link_is_consistent(tmp_path, capsys):
    massless_tool = '<inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" iyz="0" ixz="0"/></inertial>'
    path = write(tmp_path, two_link_arm(tool=massless_tool))
    code, out, _ = _run(capsys, path)
    assert code == 0 and "massless frame, not a body: not judged" in out and "M(q) singular: never" in out
    assert "links: 2 consistent, 0 degenerate, 0 inconsistent, 0 invalid; 2 not judged" in out  # base, tool


def test_exit_1_with_sign_and_repair_for_an_inconsistent_link(tmp_path, capsys):
    path = write(tmp_path, two_link_arm(second=inertial(0.05, "0.1 0 0", "0 0 0", 0.001, 0.001, 0.01)))
    code, out, _ = _run(capsys, path)
    assert code == 1 and "NOT CONSISTENT: l2" in out
    assert "izz x 0.1" in out and "repair  l2: nearest consistent I_CoM" in out


def test_exit_1_for_a_massless_body(tmp_path, capsys):
    code, out, _ = _run(capsys, write(tmp_path, two_link_arm(second="")))
    assert code == 1 and "body l2" in out and "M(q) singular: everywhere" in out


def test_base_links_count_only_with_floating_base(tmp_path, capsys):
    text = two_link_arm().replace(link("base"), link("base", inertial(1e-6, ixx=1e-6, iyy=1e-6, izz=1e-6, ixy=1e-6, iyz=1e-6, ixz=1e-6)))
    path = write(tmp_path, text)
    assert _run(capsys, path)[0] == 0
    code, out, _ = _run(capsys, path, "--floating-base")
    assert code == 1 and "all six entries equal" in out


def test_exit_2_names_the_element_and_the_rest_is_still_audited(tmp_path, capsys):
    write(tmp_path, two_link_arm(), "good.urdf")
    write(tmp_path, robot(link("a"), joint("j", "a", "ghost")), "bad.urdf")
    code, out, err = _run(capsys, tmp_path, "--json")
    assert code == 2 and "Traceback" not in err
    errors = [line for line in err.splitlines() if not line.startswith("inertiaproof: audit: ")]  # not its progress
    assert len(errors) == 1 and "joint 'j': <child link='ghost'> names no link" in errors[0]
    doc = json.loads(out)
    assert doc["files"][str(tmp_path / "good.urdf")]["status"] == "ok"
    assert doc["files"][str(tmp_path / "bad.urdf")]["status"] == "error"


def test_exit_2_on_bad_usage(tmp_path, capsys):
    assert _run(capsys, tmp_path)[0] == 2  # a folder without URDFs
    assert _run(capsys, tmp_path / "missing.urdf")[0] == 2
    code, _, err = _run(capsys, write(tmp_path, two_link_arm()), "--repair-slack", "2")
    assert code == 2 and "--repair-slack" in err


def test_json_is_keyed_by_file_and_link_and_numbers_say_what_they_are(tmp_path, capsys):
    path = write(tmp_path, two_link_arm(second=inertial(0.05, "0.1 0 0", "0 0 0", 0.001, 0.001, 0.01)))
    code, out, _ = _run(capsys, path, "--json")
    doc = json.loads(out)
    assert doc["schema"] == "inertiaproof.audit/1" and doc["summary"]["exit_status"] == code == 1
    f = doc["files"][str(path)]
    assert set(f["links"]) == {"base", "l1", "l2"}
    l2 = f["links"]["l2"]
    assert l2["verdict"] == "inconsistent" and l2["reason"].startswith("triangle inequality of I_CoM fails")
    assert l2["repair"]["change_frobenius_rel"]["kind"] == "value"
    chain = f["chains"]["l2"]
    assert chain["joints"] == ["j1", "j2"] and chain["bounds"]["lambda_min"]["kind"] in ("sampled", "lower_bound")
    assert chain["bounds"]["inf_lambda_min_sampled"]["kind"] == "sampled"


def test_link_verdicts_use_the_wording_of_inertiaproof_inertia(tmp_path, capsys):
    path = write(tmp_path, two_link_arm())
    doc = json.loads(_run(capsys, path, "--json")[1])
    r = read_urdf(path)
    for name, entry in doc["files"][str(path)]["links"].items():
        expected = next(physical_consistency(r.link(name).inertial.phi_at_com).rows())
        assert {k: entry[k] for k in expected} == expected


@settings(max_examples=25)  # each example audits with every bracket (0.4 s)
@given(st.lists(st.floats(min_value=-1e3, max_value=1e3) | st.sampled_from([0.0, 1e-300, -1e-30, 1e60, -1e60]),
                min_size=7, max_size=7))
@pytest.mark.slow
def test_any_numbers_in_range_give_a_verdict_never_a_crash(tmp_path_factory, numbers):
    second = inertial(numbers[0], "0.1 0 0", "0 0 0", *numbers[1:])
    path = write(tmp_path_factory.mktemp("fuzz"), two_link_arm(second=second))
    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(record=True) as caught, redirect_stdout(out), redirect_stderr(err):
        warnings.simplefilter("always")
        code = cli.main(["audit", str(path), "--bounds", "all"])
    assert code in (0, 1) and err.getvalue() == "" and not caught


# -- real robots ------------------------------------------------------------------------

ROBOTS = robots_folder()
needs_robots = pytest.mark.skipif(ROBOTS is None, reason="example-robot-data is not installed (test extra)")


@needs_robots
def test_panda_ur5_and_a_hand(capsys):
    files = [ROBOTS / "panda_description/urdf/panda.urdf", ROBOTS / "ur_description/urdf/ur5_robot.urdf",
             ROBOTS / "allegro_hand_description/urdf/allegro_right_hand.urdf"]
    code, out, _ = _run(capsys, *files)
    assert code == 1  # the Allegro fingertips break the triangle inequality
    for name in ("panda_link0", "panda_link7", "panda_leftfinger", "shoulder_link", "wrist_3_link", "link_3.0"):
        assert f"\n  {name} " in out
    assert "repair  link_3.0: nearest consistent I_CoM" in out and "products of inertia in the opposite sign" in out
    assert out.count("lambda_min = ") == 3 and "[sampled]" in out  # panda's two finger chains and the UR5


@needs_robots
@pytest.mark.slow
def test_sweep_of_example_robot_data():
    start = time.perf_counter()
    files = audit_paths([ROBOTS], **SWEEP, bounds="arms")
    seconds = time.perf_counter() - start
    unreadable = [p for p, f in files.items() if f["status"] == "error"]
    assert len(files) >= 60 and [p.rsplit("/", 1)[-1] for p in unreadable] == ["ur3.urdf"]
    ok = {p.rsplit("/", 1)[-1]: f for p, f in files.items() if f["status"] == "ok"}
    assert ok["panda.urdf"]["consistent"] and ok["ur5_robot.urdf"]["consistent"]
    assert set(ok["allegro_left_hand.urdf"]["not_consistent"]) == {"link_3.0", "link_7.0", "link_11.0", "link_15.0"}
    signs = {s["sign"] for f in ok.values() for link in f["links"].values() for s in link["signs"]}
    assert {"power_of_ten", "products_sign", "parallel_axis", "all_entries_equal", "point_mass",
            "negligible_inertia", "massless_with_inertia"} <= signs
    for f in ok.values():
        for entry in f["links"].values():
            assert entry["verdict"] in LABELS
            if entry["verdict"] != "consistent" and not entry["massless_frame"] and entry["inertial"]["mass"] > 0:
                assert entry["repair"] is not None
        assert all((c["bounds"] is not None) == f["serial_arm"] for c in f["chains"].values())
    assert sum(f["serial_arm"] for f in ok.values()) >= 20
    print(f"\nsweep of {len(files)} URDFs: {seconds:.2f} s")


def test_serial_arm_means_chains_differing_only_in_the_last_joint(tmp_path):
    two_fingers = two_link_arm().replace("</robot>", link("f") + joint("jf", "l1", "f", kind="prismatic", axis="1 0 0") + "</robot>")
    assert not is_serial_arm(kinematic_tree(read_urdf(write(tmp_path, two_link_arm().replace(
        "</robot>", link("h") + joint("jh", "base", "h") + "</robot>")))).chains)
    assert is_serial_arm(kinematic_tree(read_urdf(write(tmp_path, two_fingers, "f.urdf"))).chains)

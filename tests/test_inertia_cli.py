"""`inertiaproof inertia FILE` on real robot links (example-robot-data URDFs) and on hand-made boundary rows,
checked against an independent exact decision (SymPy characteristic polynomials, Descartes' rule of signs)."""

import csv
from fractions import Fraction
import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from exact_oracle import verdict_about_com, verdict_of_phi

from inertiaproof.cli import main

COLUMNS = ["name", "mass", "com_x", "com_y", "com_z", "ixx", "iyy", "izz", "ixy", "iyz", "ixz", "roll", "pitch", "yaw"]


def _robots_dir():
    """example-robot-data's URDFs under a site-packages directory (the wheel ships no Python loader)."""
    for entry in map(Path, sys.path):
        candidate = entry / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    pytest.skip("example-robot-data URDFs not found (pip install example-robot-data)")


def urdf_links():
    """One row per distinct <inertial> of every example-robot-data URDF: name, mass, origin xyz, inertia, origin rpy."""
    rows, seen = [], set()
    for path in sorted(_robots_dir().rglob("*.urdf")):
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            continue
        for link in root.iter("link"):
            inertial = link.find("inertial")
            if inertial is None:
                continue
            origin = inertial.find("origin")
            xyz = (origin.get("xyz") if origin is not None and origin.get("xyz") else "0 0 0").split()
            rpy = (origin.get("rpy") if origin is not None and origin.get("rpy") else "0 0 0").split()
            inertia = inertial.find("inertia")
            values = [inertial.find("mass").get("value"), *xyz,
                      *(inertia.get(k) for k in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")), *rpy]
            if tuple(values) not in seen:
                seen.add(tuple(values))
                rows.append([f"{path.stem}/{link.get('name')}", *values])
    return rows


def _text(x):
    """The shortest decimal that reads back as the same float."""
    return repr(float(x))


def write_csv(path, rows, columns=COLUMNS):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(columns)
        writer.writerows(rows)
    return path


def classify(path, capsys):
    code = main(["inertia", str(path), "--json"])
    return code, json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def robot_rows():
    return urdf_links()


def test_real_robot_links_match_the_exact_decision(robot_rows, tmp_path, capsys):
    code, out = classify(write_csv(tmp_path / "robots.csv", robot_rows), capsys)
    assert len(out) == len(robot_rows) > 500
    expected = [verdict_about_com(r[1], *r[5:11]) for r in robot_rows]
    got = [e["verdict"] for e in out]
    wrong = [(r[0], g, x) for r, g, x in zip(robot_rows, got, expected) if g != x]
    assert not wrong, wrong[:5]
    counts = {v: got.count(v) for v in set(got)}
    assert counts["inconsistent"] > 0 and counts["degenerate"] > 0 and counts["consistent"] > 500
    assert code == 1
    by_name = dict(zip((r[0] for r in robot_rows), out))
    assert by_name["pr2/sensor_mount_link"]["verdict"] == "inconsistent"  # PD inertia violating a triangle inequality
    assert by_name["finger_edu/finger_lower_link"]["verdict"] == "degenerate"  # izz = 0, ixx = iyy: a line mass
    assert "line mass" in by_name["finger_edu/finger_lower_link"]["reason"]
    pd_but_inconsistent = [r for r, g in zip(robot_rows, got) if g == "inconsistent" and float(r[1]) > 0
                           and np.all(np.linalg.eigvalsh(_inertia(r)) > 0)]
    assert pd_but_inconsistent, "some real links have a positive definite inertia that violates a triangle inequality"


def _inertia(row):
    ixx, iyy, izz, ixy, iyz, ixz = (float(x) for x in row[5:11])
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


BOUNDARY = [
    # name, mass, com, inertia (ixx, iyy, izz, ixy, iyz, ixz), rpy, expected
    ("ordinary box", 2, (0.1, 0.2, 0.3), (0.05, 0.04, 0.03, 0, 0, 0), (0, 0, 0), "consistent"),
    ("pd but triangle fails", 1, (0, 0, 0), (1, 1, 3, 0, 0, 0), (0, 0, 0), "inconsistent"),
    ("rod off the origin", 2, (0.1, 0.3, 0.7), (0, 1, 1, 0, 0, 0), (0.3, 0.2, 0.1), "degenerate"),
    ("plate, turned", 3, (0.11, -0.37, 0.71), (1, 2, 3, 0, 0, 0), (1, 2, 3), "degenerate"),
    ("point mass", 1, (0.1, 0.2, 0.3), (0, 0, 0, 0, 0, 0), (0, 0, 0), "degenerate"),
    ("plate with products", 1, (0, 0, 0), (2, 2, 4, 1, 0, 0), (0, 0, 0), "degenerate"),
    ("one ulp inside", 1, (0, 0, 0), (0.1, 0.2, np.nextafter(0.30000000000000004, 0), 0, 0, 0), (0, 0, 0), None),
    ("0.1 + 0.2 vs 0.3", 1, (0, 0, 0), (0.1, 0.2, 0.3, 0, 0, 0), (0, 0, 0), None),
    ("one ulp outside", 1, (0, 0, 0), (0.1, 0.2, np.nextafter(0.30000000000000004, 1), 0, 0, 0), (0, 0, 0), None),
    ("zero mass", 0, (0, 0, 0), (0.1, 0.1, 0.1, 0, 0, 0), (0, 0, 0), "inconsistent"),
]


def test_boundary_rows_only_exact_arithmetic_decides(tmp_path, capsys):
    """Verdicts on the decimals as written; where their float64 values fall in another class, both are named."""
    rows = [[n, m, *map(_text, com), *map(_text, i), *rpy] for n, m, com, i, rpy, _ in BOUNDARY]
    code, out = classify(write_csv(tmp_path / "boundary.csv", rows), capsys)
    for (name, m, com, inertia, rpy, expected), entry in zip(BOUNDARY, out):
        as_written = verdict_about_com(Fraction(_text(m)), *(Fraction(_text(x)) for x in inertia))
        as_float = verdict_about_com(m, *inertia)
        assert entry["verdict"] == as_written, name
        assert entry.get("float64_verdict", as_written) == as_float, name
        if expected is not None:
            assert as_written == expected, name
    near = {e["name"]: e for e in out}
    assert near["0.1 + 0.2 vs 0.3"]["verdict"] == "degenerate"  # 1/10 + 2/10 = 3/10: a plate, as written
    assert near["0.1 + 0.2 vs 0.3"]["float64_verdict"] == "consistent"  # 0.1 + 0.2 > 0.3 in binary floating point
    assert "as float64: consistent" in near["0.1 + 0.2 vs 0.3"]["reason"]
    assert near["one ulp outside"]["verdict"] == "inconsistent" and "float64_verdict" not in near["one ulp outside"]
    assert all(near[k]["decided_exactly"] for k in ("one ulp inside", "0.1 + 0.2 vs 0.3", "one ulp outside"))


def test_paper_columns_on_the_boundary(tmp_path, capsys):
    """Phi columns: a point mass with integer Phi, and its principal moments moved by one ulp up or down."""
    up, down = (lambda x: np.nextafter(x, np.inf)), (lambda x: np.nextafter(x, -np.inf))  # noqa: E731
    rows = [["point", 2, 2, -4, 6, 26, 20, 10, 4, 12, -6],
            ["point, moments + ulp", 2, 2, -4, 6, up(26), up(20), up(10), 4, 12, -6],
            ["point, moments - ulp", 2, 2, -4, 6, down(26), down(20), down(10), 4, 12, -6]]
    columns = ["name", "m", "h1", "h2", "h3", "I11", "I22", "I33", "I12", "I23", "I13"]
    code, out = classify(write_csv(tmp_path / "phi.csv", [[r[0], *map(_text, r[1:])] for r in rows], columns), capsys)
    assert [e["verdict"] for e in out] == [verdict_of_phi(np.array(r[1:], dtype=float)) for r in rows]
    assert [e["verdict"] for e in out] == ["degenerate", "consistent", "inconsistent"]
    assert code == 1


def test_malformed_rows_are_reported_by_number_and_the_rest_classified(tmp_path, capsys):
    good = ["good", 2, 0, 0, 0, 0.05, 0.04, 0.03, 0, 0, 0, 0, 0, 0]
    rows = [good, ["missing mass", "", 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0], good,
            ["text", "heavy", 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0], ["nan", 1, 0, 0, 0, "nan", 1, 1, 0, 0, 0, 0, 0, 0],
            ["inf", 1, 0, 0, 0, 1, "inf", 1, 0, 0, 0, 0, 0, 0], ["bad yaw", 1, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, "x"],
            ["inconsistent", 1, 0, 0, 0, 1, 1, 3, 0, 0, 0, 0, 0, 0]]
    code, out = classify(write_csv(tmp_path / "mixed.csv", rows), capsys)
    assert code == 2
    verdicts = {e["row"]: (e["verdict"], e["reason"]) for e in out}
    assert verdicts[1][0] == verdicts[3][0] == "consistent" and verdicts[8][0] == "inconsistent"
    assert verdicts[2] == ("error", "missing field mass")
    assert verdicts[4][0] == "error" and "mass" in verdicts[4][1] and "'heavy'" in verdicts[4][1]
    assert verdicts[5][0] == "error" and "ixx" in verdicts[5][1] and "not finite" in verdicts[5][1]
    assert verdicts[6][0] == "error" and "iyy" in verdicts[6][1]
    assert verdicts[7][0] == "error" and "yaw" in verdicts[7][1]


def test_text_table_and_exit_codes(tmp_path, capsys):
    good = ["good", 2, 0, 0, 0, 0.05, 0.04, 0.03, 0, 0, 0, 0, 0, 0]
    assert main(["inertia", str(write_csv(tmp_path / "ok.csv", [good, good]))]) == 0
    table = capsys.readouterr().out.splitlines()
    assert table[0].split()[:3] == ["row", "name", "verdict"] and len(table) == 3
    rod = ["rod", 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0]
    assert main(["inertia", str(write_csv(tmp_path / "rod.csv", [good, rod]))]) == 1


def test_unreadable_files_fail_in_one_line(tmp_path, capsys):
    (tmp_path / "cols.csv").write_text("a,b\n1,2\n")
    for path in (tmp_path / "missing.csv", tmp_path / "cols.csv"):
        assert main(["inertia", str(path)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and str(path) in err[0]


def test_json_input(tmp_path, capsys):
    path = tmp_path / "rows.json"
    path.write_text(json.dumps({"rows": [{"name": "rod", "mass": 1, "com_x": 0.5, "com_y": 0, "com_z": 0, "ixx": 0,
                                          "iyy": 1, "izz": 1, "ixy": 0, "iyz": 0, "ixz": 0}, "not a row"]}))
    code, out = classify(path, capsys)
    assert code == 2 and out[0]["verdict"] == "degenerate" and out[1]["verdict"] == "error"


def test_a_file_larger_than_a_chunk_streams_with_the_same_verdicts(tmp_path, capsys, monkeypatch):
    """Chunks of 7 rows (the real size is 65,536): the same entries, row numbers running on across chunks, each
    chunk's rows converted and classified on their own; a blank line is no row, a malformed row stays one."""
    from inertiaproof.model import rows as rows_module

    good = ["good", 2, 0.1, 0, 0, 0.05, 0.04, 0.03, 0, 0, 0, 0.1, 0, 0]
    rod = ["rod", 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, "", "", ""]
    bad = ["bad", 1, 0, 0, 0, 1, 1, 3, 0, 0, 0, 0, 0, 0]
    table = [good, rod, bad] * 7 + [["broken", "x", 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0]]
    path = write_csv(tmp_path / "long.csv", table)
    whole = classify(path, capsys)
    monkeypatch.setattr(rows_module, "CHUNK_ROWS", 7)
    sizes = [len(chunk) for chunk in rows_module.row_chunks(path)]
    assert sizes == [7, 7, 7, 1]
    assert classify(path, capsys) == whole
    code, out = whole
    assert code == 2 and [e["row"] for e in out] == list(range(1, 23))
    assert [e["verdict"] for e in out[:3]] == ["consistent", "degenerate", "inconsistent"] and out[-1]["verdict"] == "error"
    path.write_text(path.read_text().replace("\nrod,", "\n\nrod,", 1))
    assert classify(path, capsys) == whole


def test_a_bad_byte_deep_in_a_streamed_file_is_one_line_with_its_place(tmp_path, capsys):
    good = ["good", 2, 0, 0, 0, 0.05, 0.04, 0.03, 0, 0, 0, 0, 0, 0]
    path = write_csv(tmp_path / "bytes.csv", [good] * 5000)
    data = path.read_bytes()
    path.write_bytes(data[:-40] + b"\xff" + data[-39:])
    assert main(["inertia", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{path}:5001:" in err[0] and "0xff" in err[0]

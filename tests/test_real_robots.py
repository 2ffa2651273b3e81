"""Real robot files that engines load: every URDF of pybullet_data (the ``pybullet`` package) and of
``icub-models`` is read as pybullet reads it, with warnings on what is odd, or rejected in one line that names
what is really broken (what Pinocchio's urdfdom rejects too)."""

import io
import json
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pytest

from inertiaproof import cli

REJECTED = {  # file: what its one-line error names, and its line
    "bicycle/bike.urdf": "joint 'handlebar_to_frontwheel': <origin> attribute xyz=\"0.07, 0, -0.69\" is not a number (line 103)",
    "biped/biped2d_pybullet.urdf": "joint 'torso_to_rightleg': <limit> attribute lower=\"-1.57.\" is not a number (line 112)",
    "torus_deform.urdf": "robot 'torus' has no <link> elements (line 2)",
}


def audit_folder(folder):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = cli.main(["audit", "--bounds", "none", "--json", str(folder)])
    return code, json.loads(out.getvalue()), err.getvalue()


@pytest.mark.slow
def test_pybullet_data_is_audited():
    pybullet_data = pytest.importorskip("pybullet_data", reason="pybullet is not installed (test extra)")
    folder = Path(pybullet_data.getDataPath())
    code, doc, err = audit_folder(folder)
    files = {p: f for p, f in doc["files"].items() if p.endswith(".urdf")}  # its MJCF: tests/test_audit_mjcf.py
    unreadable = {str(Path(p).relative_to(folder)): f["error"] for p, f in files.items() if f["status"] == "error"}
    assert len(files) == 1095 and code == 2
    assert set(unreadable) == set(REJECTED)
    for name, message in REJECTED.items():
        assert unreadable[name] == f"{folder / name}: {message}"
    warned = {str(Path(p).relative_to(folder)): f["warnings"] for p, f in files.items() if f.get("warnings")}
    assert 'the XML declaration says version "0.0"' in warned["cube_small.urdf"][0]
    assert any("spherical" in w for w in warned["humanoid/humanoid.urdf"])
    assert any("NUL bytes" in w for w in warned["humanoid/humanoid.urdf"])
    assert any("$(optenv" in w for w in warned["husky/husky.urdf"])
    assert any("2 <axis> elements" in w for w in warned["quadruped/spirit40newer.urdf"])
    assert any("which Bullet reads as no limit" in w for w in warned["cube_no_rotation.urdf"])
    assert "Traceback" not in err and all(line.startswith("inertiaproof: ") for line in err.splitlines())
    assert files[str(folder / "plane_implicit.urdf")]["status"] == "ok"  # <plane> geometry: not read


def test_icub_models_are_audited():
    icub_models = pytest.importorskip("icub_models", reason="icub-models is not installed (test extra)")
    folder = Path(icub_models.get_models_path())
    code, doc, err = audit_folder(folder)
    assert len(doc["files"]) >= 10 and doc["summary"]["unreadable"] == 0, err
    assert code in (0, 1) and "Traceback" not in err
    assert doc["summary"]["links"]["consistent"] > 100

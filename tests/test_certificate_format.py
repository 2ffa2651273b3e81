"""The certificate format as a contract (inertiaproof.certificate/2): the JSON Schema in the package, the golden
certificates under tests/golden (true, false, malformed, one of each kind) as the checker answers them, and the
prover's certificates of a run against the schema."""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

import jsonschema
import pytest

from inertiaproof.verify.cli import check, verify_file

GOLDEN = sorted((Path(__file__).parent / "golden").glob("*.json"))
STATUS = {"reproved": "re-proved", "refuted": "refuted", "unproved": "not re-proved", "bad": "bad certificate"}


@pytest.fixture(scope="module")
def schema():
    text = resources.files("inertiaproof.verify").joinpath("certificate-2.schema.json").read_text()
    validator = jsonschema.Draft202012Validator(json.loads(text))
    validator.check_schema(validator.schema)
    return validator


def test_every_kind_has_golden_certificates():
    kinds = {path.name.split(".")[0] for path in GOLDEN}
    assert {k.split("-lambda")[0].split("-sigma")[0].split("-psi")[0].split("-max")[0].split("-rss")[0]
            .rsplit("-", 1)[0] if k.startswith(("product", "sum", "key")) else k for k in kinds} >= {
        "mass-matrix-spectrum-lambda_min", "mass-matrix-spectrum-lambda_max", "body-spectrum-lambda_min",
        "payload-envelope-lambda_min", "moving-mass-psi", "skew-partials-max_sigma", "product", "sum", "key-step"}
    assert {path.name.split(".")[1] for path in GOLDEN} == set(STATUS)


@pytest.mark.parametrize("path", GOLDEN, ids=lambda p: p.name)
def test_a_golden_certificate_is_answered_as_its_name_says(path, schema):
    expected = STATUS[path.name.split(".")[1]]
    out = verify_file(path)
    assert out["status"] == expected, out
    if expected != "bad certificate":
        assert not list(schema.iter_errors(json.loads(path.read_text())))
        assert out["claim"] and out["why"]
    if expected == "refuted":
        assert out["where"]["witness"] and out["where"]["sides"], out


def test_the_schema_rejects_what_the_checker_rejects(schema):
    bad = [json.loads(p.read_text()) for p in GOLDEN if ".bad." in p.name]
    assert bad and all(list(schema.iter_errors(cert)) for cert in bad)


def test_the_provers_certificates_follow_the_schema(schema, tmp_path):
    from inertiaproof.bounds.completion import complete
    from inertiaproof.bounds.certificate import spectrum_certificate
    from inertiaproof.scene import robots
    import numpy as np

    scene = robots.spatial_3r()
    theta = scene.trajectory.theta(np.array([0.0]))[0]
    cert = spectrum_certificate(scene.chain, theta, "lambda_min", 0.01, witness=np.zeros(3))
    assert not list(schema.iter_errors(cert))
    done = complete(cert, boxes=5000)
    assert not list(schema.iter_errors(done)) and check(done)["status"] == "re-proved"

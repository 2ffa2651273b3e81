import os

import inertiaproof.cli  # noqa: F401  (first: BLAS loads with one thread, as the command has it, and rounds alike)
import pytest
from hypothesis import HealthCheck, settings

from inertiaproof.suite.context import Context
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import PROFILES

settings.register_profile("ci", derandomize=True, database=None, deadline=None, max_examples=50,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture
def ctx(tmp_path):
    """A ci-profile context that writes data and counterexamples under the test's tmp_path."""
    return Context(PROFILES["ci"], seed=0, outputs=Outputs(tmp_path, tmp_path / "found"))

import os

for _threads in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):  # BLAS as the command loads it (inertiaproof.cli):
    os.environ.setdefault(_threads, "1")  # one thread, so the tests see the command's rounding

import pytest  # noqa: E402
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

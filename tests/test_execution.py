"""The execution layer (issues 16, 28): hunts split into seeded shards give the same answers on 1 worker, 2 forked
ones or 2 Dask workers, survive a killed Dask worker, never compute on more processes than workers, and
`--scheduler` without Dask is a one-line exit-2 error."""

import dataclasses
import os
import signal
import sys
import threading
import time

import numpy as np
import pytest
from hypothesis import strategies as st

from inertiaproof import cli
from inertiaproof.suite import runner
from inertiaproof.suite.context import Context
from inertiaproof.suite.execution import INSTALL_HINT, DaskExecutor, Executor, ForkExecutor, executor_for
from inertiaproof.suite.hunt import hunt, hunt_settings, is_pure, portable, shard_seed, shard_sizes
from inertiaproof.suite.outputs import Outputs
from inertiaproof.suite.profiles import PROFILES
from inertiaproof.suite.timings import without_timings

SMALL = dataclasses.replace(PROFILES["ci"], shard_examples=5)  # ci, but every hunt of more than 5 examples splits


def test_the_split_depends_on_the_profile_only():
    assert shard_sizes(20, 5) == [5, 5, 5, 5]
    assert shard_sizes(22, 5) == [5, 5, 4, 4, 4]
    assert shard_sizes(3, 60) == [3]
    assert shard_seed(0, "x", 0, 1) != shard_seed(0, "x", 0, 2) != shard_seed(0, "x", 1, 2)
    assert shard_seed(0, "x", 1, 2) == shard_seed(0, "x", 1, 2)


def test_margins_that_write_into_their_caller_stay_in_the_client():
    record = []
    assert is_pure(lambda x: x + 1.0)
    assert not is_pure(lambda x: record.append(x) or 1.0)
    k = 2.0
    assert is_pure(lambda x: k * x)


def test_a_scheduler_without_dask_is_a_one_line_exit_2_and_workers_need_no_dask(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed raises ImportError
    status = cli.main(["run", "--scheduler", "tcp://127.0.0.1:1", "--only", "EQ-geom", "--out", str(tmp_path),
                       "--quiet"])
    err = capsys.readouterr().err.strip()
    assert status == 2 and len(err.splitlines()) == 1 and INSTALL_HINT in err
    assert cli.main(["run", "--workers", "2", "--only", "EQ-geom", "EQ-schur", "--no-verify", "--out",
                     str(tmp_path), "--quiet"]) == 0
    with executor_for(2, None) as executor:
        assert isinstance(executor, ForkExecutor) and executor.lanes == 2


def slow_margin(x):
    time.sleep(0.02)
    return 1.0 + (x % 1000) / 1000.0


def violating_margin(x):
    return -1.0 if x % 7 == 3 else 1.0


@pytest.fixture(scope="module")
def dask2():
    pytest.importorskip("distributed")
    import cloudpickle

    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers cannot import this test module
    with DaskExecutor(workers=2) as executor:
        yield executor


@pytest.fixture(scope="module", params=["fork", "dask"])
def two(request):
    """Two workers: forked processes on this machine, or a Dask LocalCluster."""
    if request.param == "dask":
        yield request.getfixturevalue("dask2")
    else:
        yield ForkExecutor(2)


def test_a_run_gives_the_same_results_json_on_one_and_two_dask_workers(dask2, tmp_path):
    docs = []
    for i, executor in enumerate((Executor(), dask2)):
        run = runner.run_checks(profile=SMALL, seed=0, only=["EQ-triangle", "Thm1-nec"], out_dir=tmp_path / str(i),
                                counterexample_dir=tmp_path / "found", executor=executor)
        docs.append(without_timings(runner.results_document(run, profile="ci", seed=0, scene=None)))
    assert docs[0]["summary"] == {"HOLDS": 2, "VIOLATED": 0, "INCONCLUSIVE": 0}
    assert docs[0] == docs[1]
    on_workers = {b["label"] for b in dask2.log if b["where"] == "workers"}
    assert {"EQ-triangle", "Thm1-nec"} <= on_workers  # pure, and recording margins, went to the workers
    # (brackets on two workers: the reduced deep run below)


@pytest.mark.slow
def test_a_reduced_deep_run_gives_the_same_results_json_on_one_and_two_forked_workers(tmp_path, monkeypatch):
    """The deep profile (a Hypothesis database, hunts not derandomised, brackets), with fewer examples and a smaller
    bracket budget; each run starts from its own empty cache."""
    reduced = dataclasses.replace(PROFILES["deep"], examples=12, samples=400, rounds=12, shard_examples=4)
    docs = []
    for i, executor in enumerate((Executor(), ForkExecutor(2))):
        monkeypatch.setenv("INERTIAPROOF_CACHE", str(tmp_path / f"cache{i}"))
        run = runner.run_checks(profile=reduced, seed=0, only=["Thm4", "EQ-triangle", "Thm1-nec"],
                                out_dir=tmp_path / str(i), counterexample_dir=tmp_path / "found", executor=executor)
        docs.append(without_timings(runner.results_document(run, profile="deep", seed=0, scene=None)))
    assert docs[0]["summary"] == {"HOLDS": 3, "VIOLATED": 0, "INCONCLUSIVE": 0}
    assert docs[0] == docs[1]
    assert hunt_settings(reduced).database is not None  # the deep profile's example database was in use


def test_a_violation_is_the_first_in_shard_order_and_is_journaled_on_arrival(two, tmp_path):
    found = []
    for i, executor in enumerate((Executor(), two)):
        ctx = Context(SMALL, seed=1, outputs=Outputs(tmp_path / str(i), tmp_path / "found"), executor=executor)
        h = hunt(st.integers(0, 10**6), violating_margin, ctx, label="issue16 violation", max_examples=40)
        assert h.violation is not None
        assert (tmp_path / str(i) / "data" / "arrived-counterexamples.jsonl").read_text().count("\n") >= 1
        found.append((h.violation, h.examples, h.margins))
    assert found[0] == found[1]


@pytest.mark.slow
def test_a_killed_worker_has_its_tasks_rerun_and_the_hunt_ends_the_same(dask2):
    import distributed

    strategy = st.integers(0, 10**6)
    assert portable(strategy) is not None and is_pure(slow_margin)
    results = []
    for executor in (Executor(), dask2):
        ctx = Context(SMALL, seed=2, executor=executor)
        killed = []
        if executor is dask2:
            client = dask2.client("hunt")
            pids = client.run(os.getpid)

            def kill():
                time.sleep(1.0)  # the shards (about 0.1 s each) are under way
                pid = next(iter(pids.values()))
                os.kill(pid, signal.SIGKILL)
                killed.append(pid)

            threading.Thread(target=kill, daemon=True).start()
        h = hunt(strategy, slow_margin, ctx, label="issue16 killed worker", max_examples=200)
        results.append((h.examples, h.margins, h.worst_margin))
        if executor is dask2:
            assert killed, "the worker was not killed during the hunt"
            assert isinstance(distributed.Client, type)
    assert results[0] == results[1]


def test_an_audit_gives_the_same_files_on_one_and_two_workers(two):
    pybullet_data = pytest.importorskip("pybullet_data")
    from inertiaproof.audit.document import audit_paths

    folder = pybullet_data.getDataPath()
    paths = [os.path.join(folder, name) for name in ("r2d2.urdf", "cartpole.urdf", os.path.join("kuka_iiwa", "model.urdf"), "plane.urdf")]
    options = dict(samples=64, rounds=0, bounds="arms")
    alone, split = audit_paths(paths, **options), audit_paths(paths, executor=two, **options)
    assert list(alone) == list(split) == paths
    assert without_timings(alone) == without_timings(split)
    assert two.log[-1]["kind"] == "audit" and two.log[-1]["tasks"] == 4 and two.log[-1]["where"] == "workers"


def test_progress_is_counts_and_an_eta_in_plain_lines_off_a_terminal():
    from inertiaproof.suite.execution import Progress

    lines = []
    progress = Progress(3, "hunt x", say=lines.append, min_interval=0.0)
    for _ in range(3):
        progress.update()
    assert lines[0].startswith("hunt x: 1/3 tasks") and "ETA" in lines[0] and lines[-1] == "hunt x: 3/3 tasks"


def test_a_margin_that_records_as_it_goes_is_sent_detached_and_its_records_merged_in_shard_order(two):
    from inertiaproof.suite.hunt import collectable

    def hunt_recording(executor):
        records, counts = [], {"even": 0}

        def margin(x):
            records.append(x)
            counts["even"] += x % 2 == 0
            return 1.0

        assert collectable(margin) is not None
        ctx = Context(SMALL, seed=4, executor=executor)
        h = hunt(st.integers(0, 10**6), margin, ctx, label="issue16 records", max_examples=23)
        return h.margins, records, counts

    assert hunt_recording(Executor()) == hunt_recording(two)
    assert two.log[-1]["label"] == "issue16 records" and two.log[-1]["where"] == "workers"


def test_a_strategy_is_shipped_by_name_only_when_the_name_rebuilds_it():
    from inertiaproof.checks.pointwise import hunt_cases

    ref = portable(hunt_cases(True))
    assert repr(ref.build()) == repr(hunt_cases(True))
    assert portable(hunt_cases(True).map(lambda case: case)) is None  # .map after the call: not rebuilt by name


def test_timing_fields_are_the_listed_ones():
    doc = {"runtime_s": 1.0, "checks": [{"evidence": {"choi_seconds": 2.0, "value": 3.0, "convergence": [[0.1, 1, 2]],
                                                      "series": {"y_label": "seconds", "lines": {"d": [[1, 0.2]]}},
                                                      "other": {"y_label": "lambda", "lines": {"d": [[1, 5.0]]}}}}]}
    assert without_timings(doc) == {"checks": [{"evidence": {"value": 3.0, "series": {"y_label": "seconds"},
                                                             "other": {"y_label": "lambda", "lines": {"d": [[1, 5.0]]}}}}]}


def test_a_hunt_whose_examples_are_all_discarded_counts_none():
    """A margin of nan discards its example (assume); when every one is discarded the hunt ends with none counted
    instead of Hypothesis' Unsatisfiable."""
    h = hunt(st.integers(0, 10), lambda x: np.nan, Context(SMALL, seed=2), label="all discarded", max_examples=5)
    assert h.examples == 0 and h.violation is None


def _span(i):
    start = time.time()
    time.sleep(0.2)
    return start, time.time()


def _overlap(spans):
    """The most spans open at once."""
    events = sorted([(a, 1) for a, _ in spans] + [(b, -1) for _, b in spans])
    most = open_now = 0
    for _, step in events:
        open_now += step
        most = max(most, open_now)
    return most


def test_forked_tasks_compute_only_on_free_tokens():
    executor = ForkExecutor(2)
    with executor.computing():  # a check maps: its token goes to its tasks
        assert _overlap(executor.map(_span, range(4), kind="hunt", label="both free")) == 2
    executor.tokens.acquire()  # another lane computes
    with executor.computing():
        assert _overlap(executor.map(_span, range(4), kind="hunt", label="one free")) == 1
    executor.tokens.release()
    assert executor.tokens.acquire(block=False) and executor.tokens.acquire(block=False)  # every token came back

"""The proof-check suite's framework: the catalog, checks and how a run goes.

- ``catalog``: the paper's results with their IDs
- ``profiles``: how hard a run looks (ci, deep)
- ``registry``, ``discovery``: checks and replayers register themselves; the modules of ``inertiaproof.checks``
- ``context``, ``outputs``: what a check receives; data files and replayable counterexamples
- ``runner``: select, run, results.json, JUnit XML, the table
- ``hunt``: Hypothesis hunts run from a check; ``replay``: re-run a saved counterexample
- ``paths``, ``environment``: the cache folder; versions
"""

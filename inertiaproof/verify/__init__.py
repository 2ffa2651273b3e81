"""The independent checker: re-proves the claims of inertiaproof's certificates in ball arithmetic and exact
rationals, importing nothing of inertiaproof and no library but python-flint and the standard library, so that a
certified number can be trusted without trusting the prover (the de Bruijn criterion; compare DRAT-trim).
:mod:`.claims` names each kind's module, :mod:`.exact` reads the numbers, :mod:`.cli` is ``inertiaproof verify``.
"""

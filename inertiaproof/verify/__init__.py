"""The independent checker: re-proves the claims of inertiaproof's certificates in ball arithmetic and exact
rationals. It imports nothing of inertiaproof and no library but python-flint and the standard library, so that a
certified number can be trusted without trusting the prover (the de Bruijn criterion; compare DRAT-trim).

:mod:`.claims` names the kinds and the module proving each (:mod:`.spectrum` on :mod:`.kinematics` and
:mod:`.tree`, :mod:`.bodies`, :mod:`.product`, :mod:`.key_step`); :mod:`.exact` reads the numbers; :mod:`.cli`
is ``inertiaproof verify PATH ...``, whose ``--about`` prints the checker's size.
"""

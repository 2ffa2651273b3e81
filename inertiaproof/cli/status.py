"""Exit status of the commands, from the verdicts they print.

    0  every check HOLDS
    1  something is VIOLATED, or a check crashed
    2  bad usage or bad input (one line naming the place)
    3  something is INCONCLUSIVE and nothing is VIOLATED

A check that falls from HOLDS to INCONCLUSIVE therefore changes the exit
status, so CI can gate on it.
"""

from __future__ import annotations

from inertiaproof.result import Verdict

__all__ = ["BAD_INPUT", "EXIT_STATUS", "HOLDS", "INCONCLUSIVE", "VIOLATED", "exit_status"]

HOLDS, VIOLATED, BAD_INPUT, INCONCLUSIVE = 0, 1, 2, 3

_VERDICTS = (f"exit status: {HOLDS} every check HOLDS; {VIOLATED} something VIOLATED or a check crashed; "
             f"{BAD_INPUT} bad usage or input; {INCONCLUSIVE} something INCONCLUSIVE and nothing VIOLATED")

EXIT_STATUS = {  # command -> the meaning of its exit status (shown by --help)
    "run": _VERDICTS,
    "replay": f"exit status: {HOLDS} the counterexample no longer fails (HOLDS); {VIOLATED} it is still VIOLATED; "
              f"{BAD_INPUT} the file cannot be read; {INCONCLUSIVE} INCONCLUSIVE",
    "list": f"exit status: {HOLDS}; {BAD_INPUT} the scene cannot be read",
    "inertia": f"exit status: {HOLDS} every row is consistent; {VIOLATED} some row is not; {BAD_INPUT} bad input "
               "(the other rows are still classified)",
    "gate": f"exit status: {HOLDS} every derived object means what the lockfile says (or --update wrote it); "
            f"{VIOLATED} a meaning changed, or an object is new or gone",
    "report": f"exit status: {HOLDS} written; {BAD_INPUT} the results folder cannot be read",
    "verify": f"exit status: {HOLDS} every claim re-proved; {VIOLATED} some claim refuted at a witness; {BAD_INPUT} "
              f"a bad certificate, a results.json that does not hold together, or bad usage; {INCONCLUSIVE} some "
              "claim not re-proved and none refuted",
    "envelope": f"exit status: {HOLDS} every constant certified and re-proved, no payload of the set beyond one; "
                f"{VIOLATED} a payload of the set beyond a constant, or a certificate refuted; {BAD_INPUT} bad usage "
                f"or input; {INCONCLUSIVE} something not certified or not re-proved",
    "identify": f"exit status: {HOLDS} the fit shown certified (without the consistent fit: every identified body "
                f"consistent); {VIOLATED} the data demand inconsistent inertia (certified), some identified body is "
                f"inconsistent, or a crash; {BAD_INPUT} bad usage or input; {INCONCLUSIVE} the consistent fit not "
                "certified",
    "audit": f"exit status: {HOLDS} every moving link and every body is consistent, no body inside a link's geometry "
             f"is ruled out and every total mass is as expected (with --baseline: no new such finding); {VIOLATED} "
             f"some finding of level error (new against the baseline); {BAD_INPUT} some file cannot be read (the "
             "others are still audited) or bad usage",
}


def exit_status(results):
    """The exit status of a list of :class:`~inertiaproof.result.Result`: 0, 1 or 3 as in the module docstring."""
    results = list(results)
    if any(r.verdict == Verdict.VIOLATED or r.evidence.get("crashed") for r in results):
        return VIOLATED
    if any(r.verdict == Verdict.INCONCLUSIVE for r in results):
        return INCONCLUSIVE
    return HOLDS

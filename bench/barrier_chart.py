"""The natural law near its barrier in two charts: why trolley_2r's and passenger_platform's natural runs stay
INCONCLUSIVE in ci (issue 26).

    python bench/barrier_chart.py [--out bench/results/stiff]

inertiaproof integrates the natural law (NaturalAdaptation) in its mirror variable U_l = f(z_l), which moves
linearly; near the barrier (lambda_min(U_l) -> 0, f(Phi_hat_l) = U_l^-1 swelling) the solver's tolerance, absolute
in U, no longer controls the estimate. Here the same law is integrated in a chart with the barrier at infinity:
U_l = L_l L_l^T, L_l lower triangular with diagonal exp(d_l), the state (d_l, the strict lower part of L_l), ten
numbers like z_l; log det U_l = 2 sum d_l exactly, and L' = L phi(L^-1 U' L^-T) (phi: the lower triangle with half
its diagonal). Per run: status, the last sample reached, counted work, the Lyapunov balance error, the smallest
barrier margin lambda_min(U) / lambda_max(U) on the samples, V - V(0) - W at a few instants and the stop's note.

Then passenger_platform's run in the log-Cholesky chart and Sundman time dt/dtau = min(1, margin / 1e-6) (solve_ivp's
BDF, tau up to 1e6): whether slowing the clock where the estimate swells carries it past its closest approach.
Writes ``OUT/barrier_chart.json`` and ``OUT/barrier_chart.md``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from inertiaproof.sim import tracking
from inertiaproof.sim.adaptive import ADJOINT_INVERSE, AdaptiveLaw, NaturalAdaptation, f_inverse, f_map
from inertiaproof.sim.recipe import Recipe

ROOT = Path(__file__).resolve().parent.parent
LOWER = np.tril_indices(4, -1)
DIAGONAL = np.arange(4)
RUNS = (  # scene, method, counted budget: the ci study's natural run of the 0.25 s traverse, gre plant, alone
    ("trolley_2r", "Radau", 200_000),
    ("passenger_platform", "BDF", 60_000),
)
PROBES = (0.6, 0.7, 0.8, 1.0, 1.7)


def factor(z):
    """L (..., 4, 4) from the chart's state (..., 10)."""
    out = np.zeros(z.shape[:-1] + (4, 4))
    out[..., DIAGONAL, DIAGONAL] = np.exp(z[..., :4])
    out[..., LOWER[0], LOWER[1]] = z[..., 4:]
    return out


def lower_solve(lower, b):
    """lower^-1 b by forward substitution, batched (partial pivoting, as np.linalg.solve's, would mix the rows)."""
    x = np.zeros(np.broadcast_shapes(lower.shape, b.shape))
    for i in range(4):
        x[..., i, :] = (b[..., i, :] - np.einsum("...k,...kj->...j", lower[..., i, :i], x[..., :i, :])
                        ) / lower[..., i, i, None]
    return x


class LogCholesky(NaturalAdaptation):
    """NaturalAdaptation with the state (log diag L, strict lower L) of U = L L^T: the barrier at infinity."""

    def initial(self, theta_hat):
        lower = np.linalg.cholesky(np.linalg.inv(f_map(np.asarray(theta_hat, float))))
        return np.concatenate([np.log(lower[..., DIAGONAL, DIAGONAL]), lower[..., LOWER[0], LOWER[1]]], -1)

    def mirror(self, z):
        lower = factor(z)
        return lower @ np.swapaxes(lower, -1, -2)

    def estimate(self, z):
        inverse = lower_solve(factor(z), np.eye(4))
        return f_inverse(np.swapaxes(inverse, -1, -2) @ inverse)

    def rate(self, z, g):
        lower = factor(z)
        a = lower_solve(lower, np.swapaxes(lower_solve(lower, f_map(self.gain * g @ ADJOINT_INVERSE)), -1, -2))
        phi = np.tril(a, -1) + 0.5 * a * np.eye(4)
        moved = lower @ phi
        return np.concatenate([phi[..., DIAGONAL, DIAGONAL], moved[..., LOWER[0], LOWER[1]]], -1)

    def divergence(self, z, theta):
        f = f_map(theta)
        trace = np.einsum("...ij,...ji->...", f, self.mirror(z))
        return np.sum(trace - np.linalg.slogdet(f)[1] - 2 * z[..., :4].sum(-1) - 4.0, axis=-1) / self.gain

    def outside(self, z):
        return ~np.isfinite(z).all(-1)

    def barrier_margin(self, z):
        s = np.linalg.svd(factor(z), compute_uv=False)
        return (s[..., -1] / s[..., 0]) ** 2

    linearization = AdaptiveLaw.linearization  # forward differences


def natural_run(scene, chart):
    recipe = Recipe(str(ROOT / "scenes" / f"{scene}.toml"), "natural", "gre", horizon=1.7, timing=(0.2, 0.25))
    spec = recipe.spec()
    if chart == "log-cholesky":
        spec = dataclasses.replace(spec, law=LogCholesky(spec.law.gain))
    return recipe, spec


def chart_row(scene, method, budget, chart):
    recipe, spec = natural_run(scene, chart)
    start = time.perf_counter()
    (run,), batch = tracking.simulate(recipe.chain(), [spec], 1.7, samples=171, rtol=3e-5, method=method,
                                      max_evaluations=budget, max_seconds=900.0)
    seconds = time.perf_counter() - start
    v, _ = batch.balance_errors(run.t, run.y, 0.0)
    _, _, z, w = (part[:, 0] for part in batch.split(run.y))
    drift = {f"{t:g}": float(v[k, 0] - v[0, 0] - w[k]) for t in PROBES
             for k in [int(np.searchsorted(run.t, t - 1e-9))] if k < len(run.t)}
    return {"scene": scene, "chart": chart, "method": method, "status": run.status, "t_reached": float(run.t[-1]),
            "work": round(float(run.work)), "seconds": round(seconds, 1), "balance_error": run.balance_error,
            "min_margin": float(spec.law.barrier_margin(z).min()), "v_minus_v0_minus_w": drift, "note": run.note}


def sundman_row(scene, tau_end=1e6, reference_margin=1e-6):
    recipe, spec = natural_run(scene, "log-cholesky")
    batch = tracking.Batch(recipe.chain(), [spec])
    y0, t0 = batch.initial_state(), spec.trajectory.span[0]
    end = t0 + recipe.run_horizon()

    def clock(y):
        if not np.all(np.isfinite(y)):
            return 0.0
        with np.errstate(all="ignore"):
            margin = float(batch.per_law("barrier_margin", batch.split(y[None])[2]).min())
        return min(1.0, margin / reference_margin) if np.isfinite(margin) else 1.0

    def rhs(tau, state):
        with np.errstate(all="ignore"):
            sigma = clock(state[:-1])
            return np.append(sigma * batch.rhs(state[-1], state[:-1]), sigma)

    reached = lambda tau, state: state[-1] - end  # noqa: E731
    reached.terminal = True
    start = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, tau_end), np.append(y0, t0), method="BDF", rtol=3e-5,
                    atol=np.append(3e-5 * batch.scale(), 3e-5), events=reached)
    t, y = sol.y[-1], sol.y[:-1].T
    _, error = batch.balance_errors(t, y, 0.0)
    return {"scene": scene, "chart": "log-cholesky, Sundman time", "method": "BDF", "tau_end": tau_end,
            "t_reached": float(t[-1]), "finished": bool(t[-1] >= end), "right_hand_sides": int(sol.nfev),
            "seconds": round(time.perf_counter() - start, 1), "balance_error": float(error[0]),
            "min_margin": float(spec.law.barrier_margin(batch.split(y)[2][:, 0]).min())}


def markdown(rows, sundman):
    lines = ["# The natural law near its barrier: mirror chart against log-Cholesky (`python bench/barrier_chart.py`)",
             "", "The ci study's natural run of the 0.25 s traverse (gre plant), alone, rtol 3e-5.", "",
             "| scene | chart | method | status | last sample | counted work | s | balance error | min margin | "
             "V - V(0) - W at " + ", ".join(f"{t:g}" for t in PROBES) + " s |", "|---" * 10 + "|"]
    for r in rows:
        drift = ", ".join(f"{r['v_minus_v0_minus_w'].get(f'{t:g}', float('nan')):.2g}" for t in PROBES)
        lines.append(f"| {r['scene']} | {r['chart']} | {r['method']} | {r['status']} | {r['t_reached']:.6g} | "
                     f"{r['work']} | {r['seconds']} | {r['balance_error']:.3g} | {r['min_margin']:.2g} | {drift} |")
    lines += [""] + [f"- {r['scene']}, {r['chart']}: {r['note']}" for r in rows if r["note"]]
    s = sundman
    finished = "finished" if s["finished"] else "not finished"
    lines += ["", f"Sundman time on {s['scene']} (log-Cholesky chart, dt/dtau = min(1, margin / 1e-6), BDF to tau = "
              f"{s['tau_end']:g}): t reached {s['t_reached']:.10g} ({finished}), "
              f"{s['right_hand_sides']} right-hand sides, {s['seconds']} s, balance error {s['balance_error']:.2g}, "
              f"smallest margin {s['min_margin']:.2g}.", ""]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "stiff")
    args = parser.parse_args()
    rows = []
    for scene, method, budget in RUNS:
        for chart in ("mirror", "log-cholesky"):
            rows.append(chart_row(scene, method, budget, chart))
            print(json.dumps(rows[-1]), flush=True)
    sundman = sundman_row("passenger_platform")
    print(json.dumps(sundman), flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "barrier_chart.json").write_text(json.dumps({"runs": rows, "sundman": sundman}, indent=1) + "\n")
    (args.out / "barrier_chart.md").write_text(markdown(rows, sundman))
    print(f"written: {args.out / 'barrier_chart.json'}, {args.out / 'barrier_chart.md'}")


if __name__ == "__main__":
    main()

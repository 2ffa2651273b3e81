"""The findings on the bodies inside each link's geometry over the real corpora the tests use, as a table.

    python bench/audit_findings.py [--out bench/results/audit_findings.md] [--workers N]
    python bench/audit_findings.py --chain 100     # time the default audit of a 100-link chain with meshes

Audits (``inertiaproof audit --bounds none --json``) example-robot-data's robots folder, pybullet_data, iCub's
models (icub-models) and dm_control's suite, whichever are installed, and writes one Markdown file: per corpus how
many links each finding of :mod:`inertiaproof.audit.bodies_inside` and :mod:`inertiaproof.audit.mesh_bodies` flags
(moving or not), how many links had their geometry read, and why the others were not; then every hard flag with the
numbers of the file that make it real (mass, centre and inertia as written, and the finding's own numbers:
volumes, supports, the ellipsoid). Asserts nothing.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from inertiaproof.audit.bodies_inside import HARD, SOFT


def corpora():
    """{name: folder} of the installed corpora, found as the tests find them."""
    out = {}
    sys.path.insert(0, str(ROOT / "tests"))
    from urdf_samples import robots_folder

    if robots_folder() is not None:
        out["example-robot-data"] = robots_folder()
    for name, find in (("pybullet_data", lambda: __import__("pybullet_data").getDataPath()),
                       ("iCub", lambda: __import__("icub_models").get_models_path()),
                       ("dm_control", lambda: os.path.join(os.path.dirname(__import__("dm_control").__file__),
                                                           "suite"))):
        try:
            out[name] = Path(find())
        except ImportError:
            pass
    return out


def audit(folder, workers):
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "inertiaproof", "audit", "--bounds", "none", "--json",
                           "--workers", str(workers), str(folder)], capture_output=True, text=True, cwd=ROOT, check=False)
    return json.loads(done.stdout), time.perf_counter() - start


def timed_default(folder, workers):
    """(wall seconds, CPU seconds of the process and its workers) of the default audit of ``folder``."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "inertiaproof", "audit", "--workers", str(workers), str(folder)],
                   capture_output=True, text=True, cwd=ROOT, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    return time.perf_counter() - start, cpu


def _why(not_read):
    for key, label in (("not found", "package not found"), ("no such file", "mesh file missing"),
                       ("trimesh cannot read", "mesh not readable by trimesh"), ("no <collision>", "no geometry"),
                       ("shapes in its <geometry>", "not one shape"), ("not a URDF primitive", "other shape"),
                       ("not decided on", "other shape"), ("origin is not read", "inertial origin not read")):
        if key in not_read:
            return label
    return not_read.split(": ", 2)[-1][:60]


def tables(results):
    names = list(results)
    rules = HARD + SOFT
    counts = {name: Counter() for name in names}
    geometry = {name: Counter() for name in names}
    hard_rows = []
    for name, (doc, seconds) in results.items():
        for path, f in doc["files"].items():
            if f["status"] != "ok":
                continue
            for link, entry in f["links"].items():
                inside = entry.get("bodies_inside")
                if not inside:
                    continue
                geometry[name]["links with mass"] += 1
                g = inside.get("geometry")
                if g is None:
                    geometry[name]["no geometry"] += 1
                elif g.get("not_read"):
                    geometry[name]["not read: " + _why(g["not_read"])] += 1
                else:
                    geometry[name]["meshes read" if g.get("meshes") else "primitives read"] += 1
                    if g.get("meshes") and not all(m["fit"] for m in g["meshes"]):
                        geometry[name]["  of which a mesh not watertight (hull only)"] += 1
                for note in inside.get("not_decided", ()):
                    geometry[name]["not decided: " + note.split(":")[0]] += 1
                for rule in sorted({x["rule"] for x in inside["findings"]}):
                    counts[name][rule] += 1
                for x in inside["findings"]:
                    if x["hard"]:
                        hard_rows.append((name, str(Path(path).relative_to(doc["_folder"])), link, entry, x))
    out = ["| finding | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for rule in rules:
        out.append(f"| {rule}{' (hard)' if rule in HARD else ' (soft)'} | "
                   + " | ".join(str(counts[n][rule]) for n in names) + " |")
    out += ["", "| geometry | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for key in sorted({k for n in names for k in geometry[n]}):
        out.append(f"| {key} | " + " | ".join(str(geometry[n][key]) for n in names) + " |")
    return out, hard_rows


def mesh_chain(n, folder):
    """bench/serial_urdf.py's n-link snake with each link's cylinder also given as a collision mesh (one STL
    file, 64 sides, named by every link): the audit reads it once."""
    import trimesh

    sys.path.insert(0, str(ROOT / "bench"))
    from serial_urdf import serial_urdf

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    trimesh.creation.cylinder(radius=0.02, height=0.1, sections=64).export(folder / "rod.stl")
    collision = ('<collision><origin xyz="0.05 0 0" rpy="0 1.5707963267948966 0"/><geometry>'
                 '<mesh filename="rod.stl"/></geometry></collision>\n  </link>')
    text = serial_urdf(n).replace("</inertial>\n  </link>", "</inertial>\n    " + collision)
    (folder / f"serial_{n}_meshes.urdf").write_text(text)
    return folder / f"serial_{n}_meshes.urdf"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(ROOT / "bench" / "results" / "audit_findings.md"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--chain", type=int, metavar="N", help="only time the default audit of an N-link chain whose "
                        "links have a collision mesh (written to a temporary folder)")
    args = parser.parse_args(argv)
    if args.chain:
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            path = mesh_chain(args.chain, folder)
            start = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "inertiaproof", "audit", str(path)], capture_output=True,
                                  text=True, cwd=ROOT, check=False)
            print(done.stdout.strip().splitlines()[-1])
            print(f"{args.chain}-link chain with meshes: exit {done.returncode}, {time.perf_counter() - start:.1f} s")
        return 0
    results = {}
    for name, folder in corpora().items():
        doc, seconds = audit(folder, args.workers)
        doc["_folder"] = str(folder)
        results[name] = (doc, seconds)
        print(f"{name}: {len(doc['files'])} files in {seconds:.1f} s", file=sys.stderr)
    table, hard_rows = tables(results)
    default = None
    if "example-robot-data" in results:
        default = timed_default(corpora()["example-robot-data"], args.workers)
        print(f"default audit of example-robot-data: {default[0]:.1f} s wall, {default[1]:.1f} s CPU", file=sys.stderr)
    lines = ["# Findings on the bodies inside each link's geometry, on the real corpora", "",
             "From `python bench/audit_findings.py` (`inertiaproof audit --bounds none --json` per corpus, "
             f"`--workers {args.workers}`). Links with a finding, per finding (a link counts once per finding; "
             "moving links and fixed ones alike). Hard findings are theorems about every body inside the link's "
             "collision geometry (visual where it has none) with density at most 22,600 kg/m^3; soft ones are "
             "notes.", "", *table, "",
             "Seconds per corpus (audit with `--bounds none`, whole process): "
             + ", ".join(f"{n} {s:.1f} s ({len(d['files'])} files)" for n, (d, s) in results.items())
             + ("" if default is None else f". The default audit (`inertiaproof audit --workers {args.workers}` on "
                f"example-robot-data's robots folder, mass-matrix bounds of the arms included): {default[0]:.1f} s "
                f"wall, {default[1]:.1f} s CPU of the process and its workers; the wall clock counts whatever else "
                f"ran on the machine (load average {os.getloadavg()[0]:.1f} at the end)."), "",
             f"## Every hard flag ({len(hard_rows)}), with the numbers of the file", "",
             "| corpus | file | link | line | rule | mass, CoM, inertia as written | what shows it |", "|---|---|---|---|---|---|---|"]
    for name, path, link, entry, x in hard_rows:
        written = entry.get("inertial") or {}
        six = written.get("inertia") or {}
        numbers = (f"m {written.get('mass')}, c ({', '.join(f'{v:g}' for v in written.get('com', []))}), "
                   + " ".join(f"{k} {six[k]:g}" for k in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz") if k in six))
        line = (entry.get("location") or {}).get("startLine", "")
        message = x["message"].split(": ", 1)[-1].replace("|", "/")
        lines.append(f"| {name} | {path} | {link} | {line} | {x['rule']} | {numbers} | {message} |")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(table))
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())

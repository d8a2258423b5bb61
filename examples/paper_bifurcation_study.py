#!/usr/bin/env python3
"""The paper's nonlinear study (Yao et al. 2023, section 5.3, Fig. 9): four
designs taken from the Pareto front of the paper's optimisation, each with the
new and the worn tread, their linear and nonlinear critical speeds and the
type of the hunting bifurcation.

    python3 examples/paper_bifurcation_study.py [--railride build/railride]

1. NSGA-II over examples/paper-optimisation.ini (population 1000, 100
   generations, seed 1) gives the front.
2. The designs: A the front's best zeta_high, B its best zeta_low, C its best
   std_zeta among the designs stable at both robust points (zeta_low < 0 and
   zeta_high < 0: the paper's C is robust, poorly damped, but stable), D the
   balanced one: the least distance to the ideal point with each objective
   scaled to 0..1 over the front.
3. Each is written as DIR/paper-design-X.ini (base = type1; DIR the folder
   --designs-dir names, never the shipped examples) and run through
   `railride bifurcation --profile new|worn --json` (100-600 km/h).
Prints the README's table (Markdown).

    python3 examples/paper_bifurcation_study.py --designs-dir /tmp/designs
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
KEYS = {  # Pareto CSV column (key_SI-unit) -> (section, key, unit scale, unit)
    "primary.longitudinal_stiffness_n_per_m": ("primary", "longitudinal_stiffness", 1e-6, "kN/mm"),
    "lateral_damper.damping_n_s_per_m": ("lateral_damper", "damping", 1e-3, "kN.s/m"),
    "yaw_damper.damping_n_s_per_m": ("yaw_damper", "damping", 1e-3, "kN.s/m"),
    "yaw_damper.series_stiffness_n_per_m": ("yaw_damper", "series_stiffness", 1e-6, "MN/m"),
}


def front(rr, population, generations):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "paper")
        subprocess.run([rr, "optimise", os.path.join(HERE, "paper-optimisation.ini"), "--population",
                        str(population), "--generations", str(generations), "--seed", "1", "--output", out],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        with open(out + "-pareto.csv") as f:
            return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def choose(rows):
    objs = ("zeta_low", "zeta_high", "std_zeta")
    lo = {o: min(r[o] for r in rows) for o in objs}
    hi = {o: max(r[o] for r in rows) for o in objs}
    scaled = lambda r: sum(((r[o] - lo[o]) / (hi[o] - lo[o])) ** 2 for o in objs)
    return {"A": min(rows, key=lambda r: r["zeta_high"]), "B": min(rows, key=lambda r: r["zeta_low"]),
            "C": min((r for r in rows if r["zeta_low"] < 0 and r["zeta_high"] < 0), key=lambda r: r["std_zeta"]),
            "D": min(rows, key=scaled)}


def write_design(name, r, why, where):
    path = os.path.join(where, f"paper-design-{name}.ini")
    lines = [f"# Design {name} of the paper's study ({why}), from the Pareto front of",
             "# examples/paper-optimisation.ini (population 1000, 100 generations, seed 1;",
             "# examples/paper_bifurcation_study.py; the index's band edge max(10 Hz, f_K)).",
             "# Objectives on the front:",
             f"#   zeta_low {r['zeta_low']:.4f}, zeta_high {r['zeta_high']:.4f}, std_zeta {r['std_zeta']:.4f}",
             "[vehicle]", "base = type1", f"name = paper-design-{name}"]
    by_section = {}
    for col, (sec, key, scale, unit) in KEYS.items():
        by_section.setdefault(sec, []).append(f"{key} = {r[col] * scale:.6g} {unit}")
    for sec, kv in by_section.items():
        lines += [f"[{sec}]"] + kv
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def bifurcation(rr, path, profile):
    out = subprocess.run([rr, "bifurcation", path, "--profile", profile, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def speed(x):
    return "-" if x is None else f"{x:.1f}"


def table_row(name, why, r, prof, d):
    """One row of the README's table: the design's parameters (Pareto CSV columns) and
    its bifurcation (`railride bifurcation --json`)."""
    lin = d["linear_critical_speed_kmh"]
    out_of_range = lin is not None and lin > 600
    kind = d["type"] + (" (Hopf above 600 km/h)" if out_of_range else "")
    return (f"| {name} ({why}) | {r['primary.longitudinal_stiffness_n_per_m'] * 1e-6:.1f} "
            f"| {r['lateral_damper.damping_n_s_per_m'] * 1e-3:.1f} "
            f"| {r['yaw_damper.damping_n_s_per_m'] * 1e-3:.0f} "
            f"| {r['yaw_damper.series_stiffness_n_per_m'] * 1e-6:.2f} | {prof} | {speed(lin)} "
            f"| {speed(d['nonlinear_critical_speed_kmh'])} | {kind} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--railride", default=os.path.join(HERE, "..", "build", "railride"))
    ap.add_argument("--population", type=int, default=1000)
    ap.add_argument("--generations", type=int, default=100)
    ap.add_argument("--treads", default="new,worn", help="the treads to study, comma separated")
    ap.add_argument("--designs-dir", required=True,
                    help="where paper-design-{A,B,C,D}.ini are written (not the shipped examples/)")
    a = ap.parse_args()
    if os.path.realpath(a.designs_dir) == os.path.realpath(HERE):
        ap.error("--designs-dir: name a folder of your own; the shipped designs in examples/ are not rewritten")
    os.makedirs(a.designs_dir, exist_ok=True)
    why = {"A": "best zeta_high", "B": "best zeta_low", "C": "best std_zeta, stable", "D": "balanced"}
    designs = choose(front(a.railride, a.population, a.generations))
    print("| design | k_px (kN/mm) | c_sy (kN s/m) | c_yaw (kN s/m) | k_yaw (MN/m) | tread "
          "| linear critical (km/h) | nonlinear critical (km/h) | bifurcation |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name in "ABCD":
        r = designs[name]
        path = write_design(name, r, why[name], a.designs_dir)
        for prof in a.treads.split(","):
            print(table_row(name, why[name], r, prof, bifurcation(a.railride, path, prof)))
        sys.stdout.flush()


if __name__ == "__main__":
    main()

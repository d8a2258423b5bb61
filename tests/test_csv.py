"""Every CSV railride writes reads back with Python's csv module and with a
plain pandas.read_csv: one header, unique names, every row as wide as the
header, numbers where numbers are expected, no comment lines. Names with
commas (objectives such as index@350,0.17) are quoted. Every column name
carries its unit (freq_hz, real_per_s, psd_..._m2s-4_per_hz,
yaw_damper.damping_n_s_per_m) unless the quantity is dimensionless."""
import csv
import io
import os
import re
import subprocess
import sys
import tempfile

import pandas as pd

from pycheck import check, done  # tests/pycheck.py

cli = os.environ["RR_CLI"]
src = os.environ["RR_SOURCE_DIR"]
tmp = tempfile.mkdtemp(prefix="rr_csv_")


def run(*args):
    r = subprocess.run([cli, *args], capture_output=True, text=True)
    check(r.returncode == 0, "%s exits 0: %s" % (" ".join(args), r.stderr[-300:]))
    return r.stdout


# a unit at the end of the name ...
UNIT = re.compile(r"_(hz|m|rad|n|nm|kmh|s|deg|per_s|per_s2|rad_per_s|n_per_m|n_s_per_m|kg|kg_m2|n_m_per_rad|m2s-4_per_hz|m2_per_hz)$", re.IGNORECASE)
# ... or a dimensionless quantity (shares, indices, flags, counts, names)
DIMENSIONLESS = re.compile(r"^(branch|conicity|stability_index(_const|_sdf)?|zeta_max|stable|mac|e_(carbody|frames|wheelsets)|"
                           r"(frame_)?roll_share|hunting_related|index_source|dissipation|input|vehicle|sperling_(const|sdf|weight|weight2)|(wk|wd|wb_en12299)_weight2|n_mv_(const|sdf)|sweep|"
                           r"max_floquet_modulus|symmetric|residual|welch_sigma_rel|generation|evaluations|seconds|front_size|"
                           r"hypervolume|feasible|violation|objective:.*)$")


def check_units(name, head, objectives):
    for col in head:
        ok = col in objectives or UNIT.search(col) or DIMENSIONLESS.match(col)
        check(ok, "%s: column %r names its unit" % (name, col))


def check_csv(name, text, must_have=(), objectives=(), strings=("input", "vehicle", "sweep", "index_source")):
    check(not any(l.startswith("#") for l in text.splitlines()), "%s: no comment lines" % name)
    rows = list(csv.reader(io.StringIO(text)))
    check(len(rows) >= 2, "%s: a header and rows" % name)
    if len(rows) < 2:
        return
    head = rows[0]
    check(len(set(head)) == len(head), "%s: unique column names %s" % (name, head))
    check(all(len(r) == len(head) for r in rows[1:]), "%s: every row has %d fields" % (name, len(head)))
    df = pd.read_csv(io.StringIO(text))
    check(list(df.columns) == head, "%s: pandas reads the same columns" % name)
    check(len(df) == len(rows) - 1, "%s: pandas reads every row" % name)
    for col in must_have:
        check(col in df.columns, "%s: column %s" % (name, col))
    num = [c for c in head if c not in strings]
    check(all(pd.api.types.is_numeric_dtype(df[c]) for c in num), "%s: numeric columns %s" % (name, df.dtypes.to_dict()))
    check_units(name, head, objectives)


check_csv("locus", run("locus", "--range", "100:300:3"), ["speed_kmh", "freq_hz", "real_per_s", "imag_rad_per_s"])
check_csv("locus over conicity", run("locus", "--over", "conicity", "--range", "0.1:0.3:3"), ["conicity"])
check_csv("map", run("map", "--speeds", "200:300:2", "--conicities", "0.1:0.2:2"), ["stability_index", "stable"])
check_csv("sweep", run("sweep", "--x", "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:2", "--y",
                       "yaw_damper.series_stiffness=1 MN/m:30 MN/m:2", "--objective", "index@350,0.17;fmax=20"),
          ["yaw_damper.damping_n_s_per_m", "index@350,0.17;fmax=20", "k_opt_n_per_m"], ["index@350,0.17;fmax=20"])
check_csv("sweep sperling", run("sweep", "--x", "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:2", "--y",
                                "yaw_damper.series_stiffness=1 MN/m:30 MN/m:2", "--objective", "sperling@350,0.17,8.6875"),
          ["sperling@350,0.17,8.6875"], ["sperling@350,0.17,8.6875"])
check_csv("sweep speed", run("sweep", "--x", "speed=200:400:3", "--objective", "index@0,0.2"), ["speed_kmh"], ["index@0,0.2"])
check_csv("frf", run("frf", "--speed", "350", "--conicity", "0.17", "--band", "1:10:4"), ["f_hz", "x_m", "re_per_s2"])
check_csv("damper", run("damper"), ["freq_hz"])
run("ride", "--speed", "350", "--conicity", "0.17,0.2", "--psd", os.path.join(tmp, "psd.csv"))
check_csv("ride --psd", open(os.path.join(tmp, "psd.csv")).read(), ["f_hz", "psd_c0.2_x0m_m2s-4_per_hz", "sperling_weight"])
run("ride", "--speed", "350", "--conicity", "0.2", "--direction", "both", "--psd", os.path.join(tmp, "vpsd.csv"))
check_csv("ride --direction both --psd", open(os.path.join(tmp, "vpsd.csv")).read(),
          ["f_hz", "track_psd_m2_per_hz", "psd_x0m_m2s-4_per_hz", "lateral_psd_x0m_m2s-4_per_hz", "wb_en12299_weight2"])
run("validate", "--speed", "350", "--direction", "vertical", "--duration", "60", "--nseg", "1024", "--psd",
    os.path.join(tmp, "vval.csv"))
check_csv("validate --direction vertical --psd", open(os.path.join(tmp, "vval.csv")).read(),
          ["f_hz", "welch_x0m_m2s-4_per_hz", "pem_x0m_m2s-4_per_hz"])
run("validate", "--speed", "350", "--conicity", "0.2", "--duration", "64", "--psd", os.path.join(tmp, "val.csv"))
check_csv("validate --psd", open(os.path.join(tmp, "val.csv")).read(), ["f_hz", "pem_x0m_m2s-4_per_hz", "welch_sigma_rel"])
check_csv("compare", run("compare", "--conicities", "0.1:0.3:2", "--csv"), ["stability_index_sdf"])
check_csv("simulate", run("simulate", "--speed", "300", "--profile", "worn", "--duration", "0.5", "--fs", "50"),
          ["t_s", "y_w1_m", "psi_c_rad", "Fy_w1_N"])
check_csv("bifurcation", run("bifurcation", "--profile", "worn", "--speeds", "400:600", "--csv"), ["speed_kmh", "amplitude_m"])
check_csv("bifurcation scan", run("bifurcation", "--profile", "worn", "--speeds", "480:500", "--method", "scan", "--step", "10",
                                  "--settle", "2", "--csv"), ["sweep", "amplitude_m", "frequency_hz"])
prob = os.path.join(tmp, "p.ini")
with open(prob, "w") as fp:
    fp.write("[problem]\npopulation = 8\ngenerations = 1\noutput = %s\n[variables]\n"
             "yaw_damper.series_stiffness = 1 MN/m .. 30 MN/m\n[objectives]\nobjective = index@350,0.17 minimize\n"
             "objective = sperling@350,0.17,8.6875 minimize\n" % os.path.join(tmp, "opt"))
run("optimise", prob)
objs = ["index@350,0.17", "sperling@350,0.17,8.6875"]
check_csv("optimise pareto", open(os.path.join(tmp, "opt-pareto.csv")).read(), ["yaw_damper.series_stiffness_n_per_m"] + objs, objs)
check_csv("optimise history", open(os.path.join(tmp, "opt-history.csv")).read(), ["generation", "hypervolume"])
done("csv")

"""Every CSV railride writes reads back with Python's csv module and with a
plain pandas.read_csv: one header, unique names, every row as wide as the
header, numbers where numbers are expected. Names with commas (objectives
such as index@350,0.17) are quoted."""
import csv
import io
import os
import subprocess
import sys
import tempfile

import pandas as pd

cli = os.environ["RR_CLI"]
src = os.environ["RR_SOURCE_DIR"]
passed = failed = 0
tmp = tempfile.mkdtemp(prefix="rr_csv_")


def check(cond, what):
    global passed, failed
    if cond:
        passed += 1
    else:
        failed += 1
        print("FAIL:", what, file=sys.stderr)


def run(*args):
    r = subprocess.run([cli, *args], capture_output=True, text=True)
    check(r.returncode == 0, "%s exits 0: %s" % (" ".join(args), r.stderr[-300:]))
    return r.stdout


def check_csv(name, text, must_have=()):
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
    num = [c for c in head if c not in ("input",)]
    check(all(pd.api.types.is_numeric_dtype(df[c]) for c in num), "%s: numeric columns %s" % (name, df.dtypes.to_dict()))


check_csv("locus", run("locus", "--range", "100:300:3"), ["speed_kmh", "freq_hz", "roll_share"])
check_csv("map", run("map", "--speeds", "200:300:2", "--conicities", "0.1:0.2:2"), ["stability_index", "stable"])
check_csv("sweep", run("sweep", "--x", "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:2", "--y",
                       "yaw_damper.series_stiffness=1 MN/m:30 MN/m:2", "--objective", "index@350,0.17;fmax=20"),
          ["index@350,0.17;fmax=20"])
check_csv("sweep sperling", run("sweep", "--x", "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:2", "--y",
                                "yaw_damper.series_stiffness=1 MN/m:30 MN/m:2", "--objective", "sperling@350,0.17,8.6875"),
          ["sperling@350,0.17,8.6875"])
check_csv("frf", run("frf", "--speed", "350", "--conicity", "0.17"), ["f_hz"])
check_csv("damper", run("damper"), ["freq_hz"])
run("ride", "--speed", "350", "--conicity", "0.17,0.2", "--psd", os.path.join(tmp, "psd.csv"))
check_csv("ride --psd", open(os.path.join(tmp, "psd.csv")).read(), ["f_hz"])
run("validate", "--speed", "350", "--conicity", "0.2", "--duration", "64", "--psd", os.path.join(tmp, "val.csv"))
check_csv("validate --psd", open(os.path.join(tmp, "val.csv")).read(), ["f_hz"])
prob = os.path.join(tmp, "p.ini")
with open(prob, "w") as fp:
    fp.write("[problem]\npopulation = 8\ngenerations = 1\noutput = %s\n[variables]\n"
             "yaw_damper.series_stiffness = 1 MN/m .. 30 MN/m\n[objectives]\nobjective = index@350,0.17 minimize\n"
             "objective = sperling@350,0.17,8.6875 minimize\n" % os.path.join(tmp, "opt"))
run("optimise", prob)
check_csv("optimise pareto", open(os.path.join(tmp, "opt-pareto.csv")).read(), ["index@350,0.17", "sperling@350,0.17,8.6875"])
print("csv: %d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)

"""The Python binding against the C library's own answers (the CLI's JSON)."""
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.environ["RR_SOURCE_DIR"], "python"))
import railride  # noqa: E402
from pycheck import check, done  # tests/pycheck.py

cli = os.environ["RR_CLI"]


d = railride.Design("type1", ["yaw_damper.series_stiffness"], ["zeta_low", "zeta_high", "std_zeta", "index@300,0.3"])
f = d.evaluate([10e6])
ref = json.loads(subprocess.run([cli, "robust", "--json"], capture_output=True, check=True, text=True).stdout)
check(abs(f[0] - ref["zeta_low"]) < 1e-13 and abs(f[1] - ref["zeta_high"]) < 1e-13 and abs(f[2] - ref["std_zeta"]) < 1e-12,
      "robust indices equal the CLI's")
modes = json.loads(subprocess.run([cli, "modes", "--speed", "300", "--conicity", "0.3", "--json"],
                                  capture_output=True, check=True, text=True).stdout)
check(abs(f[3] - modes["stability_index"]) < 1e-11, "index equals the CLI's (fast route vs full dgeev: ~1e-13 apart)")
# the index's rule as objective modifiers, and a paper-mode SDF design variable
g = railride.Design("type1", ["yaw_damper.sdf_k1"], ["index@350,0.17;fmax=20;wmin=0;rmax=1", "critical_speed@0.6",
                                                      "index@350,0.17;sdf=paper"])
fg = g.evaluate([1.5])
all_modes = json.loads(subprocess.run([cli, "modes", "--speed", "350", "--conicity", "0.17", "--json", "--fmax", "20",
                                       "--wmin", "0", "--rmax", "1"], capture_output=True, check=True, text=True).stdout)
check(abs(fg[0] - all_modes["stability_index"]) < 1e-11, "modifiers reach the index")
check(abs(fg[1] - 422.1) < 0.05, "critical speed over any mode (%g)" % fg[1])
sdf = json.loads(subprocess.run([cli, "modes", "type1", "--sdf", "paper", "--speed", "350", "--conicity", "0.17", "--json"],
                                capture_output=True, check=True, text=True).stdout)
check(abs(fg[2] - sdf["stability_index"]) < 1e-12, "paper-mode SDF index equals the CLI's")
X = np.array([[5e6], [10e6], [20e6], [-1.0]])
F = d.evaluate_batch(X)
check(F.shape == (4, 4), "batch shape")
check(np.allclose(F[1], f, rtol=0, atol=1e-14), "batch row equals single evaluation")
check(np.all(np.isnan(F[3])), "invalid design gives NaN")
try:
    railride.Design("type1", ["primary.stifness"], ["zeta_low"])
    check(False, "unknown key raises")
except railride.RailrideError as e:
    check("primary.stifness" in str(e), "error names the key")
try:
    d.evaluate_batch(np.zeros((2, 3)))
    check(False, "wrong width raises")
except ValueError:
    check(True, "wrong width raises")
for ex in ("python_loop.py", "pymoo_problem.py"):
    r = subprocess.run([sys.executable, os.path.join(os.environ["RR_SOURCE_DIR"], "examples", ex)], capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=os.path.join(os.environ["RR_SOURCE_DIR"], "python")))
    check(r.returncode == 0 and r.stdout.strip(), "example %s runs: %s" % (ex, r.stderr[-300:]))
# Vehicle: the library's analyses as numpy arrays, against the CLI's JSON and CSV
v = railride.Vehicle("type1")
md = v.modes(350, 0.17)
cm = json.loads(subprocess.run([cli, "modes", "--speed", "350", "--conicity", "0.17", "--json"], capture_output=True, check=True, text=True).stdout)
check(abs(md["stability_index"] - cm["stability_index"]) < 1e-11 and len(md["freq_hz"]) == len(cm["modes"]) + int(np.sum(md["imag"] == 0))
      and np.allclose(md["freq_hz"][md["imag"] > 0], [m["freq_hz"] for m in cm["modes"]], rtol=1e-12)
      and md["name"][:len(cm["modes"])] == [m["name"] for m in cm["modes"]], "Vehicle.modes equals modes --json")
# revision 3 and the shapes: unique names, real roots flagged, shapes as a complex array
# equal to the CLI's amplitude and phase, each an eigenvector of the model (unit norm)
check(len(set(md["name"])) == len(md["name"]), "mode names unique: %s" % md["name"])
check(md["oscillatory"].sum() == len(cm["modes"]) and not md["oscillatory"][-1], "real roots flagged")
sh = md["shape"]
check(sh.shape == (len(md["name"]), 17) and sh.dtype == np.complex128 and np.allclose(np.linalg.norm(sh, axis=1), 1),
      "shapes: modes x 17 DOFs, unit norm")
k = md["index_mode"]
js = cm["modes"][k]["shape"]
amp = np.array([e["amplitude"] for e in js]) * np.exp(1j * np.radians([e["phase_deg"] for e in js]))
check(np.allclose(amp, sh[k], atol=1e-9) and [e["dof"] for e in js] == md["dofs"], "the index mode's shape as --json")
check(md["index_source"] == "hunting" and md["frame_roll_share"].shape == md["roll_share"].shape, "index source")
v2 = railride.Vehicle("type1")
check(v2.modes(430, 0.6, fmax=10)["index_source"] == "unstable_outside_hunting" and
      v2.stability_index(430, 0.6, fmax=10) > 0, "an unstable mode above a fixed band sets a positive index")
m430 = v2.modes(430, 0.6)
check(m430["index_source"] == "hunting" and abs(m430["fmax_hz"] - 25.13) < 0.01 and v2.stability_index(430, 0.6) > 0,
      "the band edge at f_K (25.13 Hz) takes in the 10.1 Hz bogie mode: %s" % m430["fmax_hz"])
check(np.isnan(v2.stability_index(350, 0.17, fmax=0.1)), "an undefined index is NaN")
check(abs(v2.band_edge(350, 0.4) - 16.700206797433935) < 1e-9 and v2.band_edge(250, 0.05) == 10 and
      v2.band_edge(350, 0.4, fmax=10) == 10, "Vehicle.band_edge: max(10 Hz, f_K), or the fixed fmax")
rb = v.robust()
check(all(abs(rb[k] - ref[k]) < 1e-12 for k in ("zeta_low", "zeta_high", "std_zeta")), "Vehicle.robust equals robust --json")
check(abs(v.critical_speed(0.4) - 524.7) < 0.05 and np.isnan(v.critical_speed(0.05)), "Vehicle.critical_speed")
mp = v.map([250, 350], [0.05, 0.4])
check(abs(mp[0, 0] - ref["zeta_low"]) < 1e-12 and abs(mp[1, 1] - ref["zeta_high"]) < 1e-12, "Vehicle.map at the robust points")
L = 17.375 / 2
rj = json.loads(subprocess.run([cli, "ride", "--speed", "350", "--conicity", "0.17", "--json"], capture_output=True, check=True, text=True).stdout)
rd = v.ride(350, 0.17)  # the library's default floor points, +L, 0, -L, as the CLI's
pts = rj["results"][0]["points"]
check(len(rd["x"]) == 3 and all(abs(rd["x"][i] - pts[i]["x"]) == 0 for i in range(3)), "Vehicle.ride's default points")
check(all(abs(rd[k][i] - pts[i][k]) <= 1e-12 * abs(pts[i][k]) for k in ("rms", "sperling", "sperling_gb", "wd_rms")
          for i in range(3)) and rd["stable"] is True and rj["results"][0]["stable"] is True,
      "Vehicle.ride equals ride --json to 1e-12")
# an unstable operating point: no ride comfort, unless asked for the linear response
ru = v.ride(450, 0.6)
rl = v.ride(450, 0.6, when_unstable="linear")
uj = json.loads(subprocess.run([cli, "ride", "--speed", "450", "--conicity", "0.6", "--json"], capture_output=True,
                               check=True, text=True).stdout)["results"][0]
check(not ru["stable"] and np.all(np.isnan(ru["sperling"])) and ru["zeta_max"] >= 0 and np.all(np.isfinite(rl["sperling"]))
      and uj["stable"] is False and all(p["sperling"] is None for p in uj["points"]),
      "unstable at 450 km/h, 0.6: the ride undefined in Python and the CLI alike")
vu = v.vertical_ride(450, lateral=0.6)
check(not vu["lateral_stable"] and np.all(np.isnan(vu["n_mv"])) and np.all(np.isfinite(vu["wb_p95"])),
      "vertical_ride at an unstable lateral point: EN 12299 undefined, the vertical side given")
try:
    v.ride(350, 0.17, spectrum="tbt3352-vertical")
    check(False, "Python's ride refuses a vertical spectrum as the lateral input")
except railride.RailrideError as ex:
    check("lateral" in str(ex), "Python's ride refuses a vertical spectrum as the CLI does: %s" % ex)
f, H = v.frf(350, 0.17, points=(0.0,))
check(H.shape == (400, 1, 4) and H.dtype == np.complex128 and np.all(np.isfinite(H)), "Vehicle.frf shape")
# the vertical model: ride, modes, FRF and matrices as the CLI gives them; the PSD integrates to the RMS
vj = json.loads(subprocess.run([cli, "ride", "--speed", "350", "--conicity", "0.17", "--direction", "both", "--json"],
                               capture_output=True, check=True, text=True).stdout)["points"]
vr = v.vertical_ride(350, lateral=0.17)
check(all(abs(vr["wb_p95"][i] - vj[i]["wb_5s"]["p95"]) < 1e-15 and abs(vr["n_mv"][i] - vj[i]["n_mv"]) < 1e-14
          and abs(vr["sperling"][i] - vj[i]["sperling"]) < 1e-14 and abs(vr["wd_p95"][i] - vj[i]["lateral"]["wd_p95"]) < 1e-15
          for i in range(3)), "Vehicle.vertical_ride equals ride --direction both --json")
fz, Gz = vr["f"], vr["psd"]
check(np.allclose(np.sqrt(np.sum(0.5 * (Gz[1:] + Gz[:-1]) * np.diff(fz)[:, None], axis=0)), vr["rms"], rtol=1e-12),
      "vertical PSD integrates to the RMS")
mj = json.loads(subprocess.run([cli, "modes", "--direction", "vertical", "--json"], capture_output=True, check=True,
                               text=True).stdout)
vm = v.vertical_modes()
check(np.allclose(vm["freq_hz"], [m["freq_hz"] for m in mj["modes"]], rtol=1e-14) and vm["name"] == [m["name"] for m in mj["modes"]]
      and vm["energy"].shape == (7, 7), "Vehicle.vertical_modes equals modes --direction vertical")
fv, Hv, Qv = v.vertical_frf(350)
mats = v.vertical_matrices()
w = 2 * np.pi * fv[17]
D = mats["K"] + 1j * w * mats["C"] - w * w * mats["M"]
e = np.exp(-1j * w * (mats["x_wheelsets"][0] - mats["x_wheelsets"]) / (350 / 3.6))
check(np.allclose(np.linalg.solve(D, (mats["BK"] + 1j * w * mats["BC"]) @ e), Qv[17], rtol=1e-11, atol=0),
      "Vehicle.vertical_frf's coordinates solve the 7x7 system from vertical_matrices")
check(Hv.shape == (400, 3) and Qv.shape == (400, 7), "vertical FRF shapes")
v.close()
try:
    v.modes(350, 0.17)
    check(False, "a closed Vehicle raises")
except railride.RailrideError:
    check(True, "a closed Vehicle raises")

# a closed design raises instead of crashing; the version is the library's
d2 = railride.Design("type1", ["primary.longitudinal_stiffness"], ["zeta_low"])
d2.close()
try:
    d2.evaluate([50e6])
    check(False, "evaluate after close raises")
except railride.RailrideError as e:
    check("closed" in str(e), "evaluate after close raises: %s" % e)
check(railride.__version__ == railride.library().rr_version().decode(), "__version__ is the library's")

# pip install . (offline, no build isolation) into a scratch target: the package carries its library
if os.environ.get("RR_PIP_TEST", "1") == "1":
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ)
        env.pop("RAILRIDE_LIB", None)
        env["RAILRIDE_LIB"] = os.environ.get("RAILRIDE_LIB", "")
        if not env["RAILRIDE_LIB"]:
            env.pop("RAILRIDE_LIB")
        r = subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps",
                            "--target", tmp, os.environ["RR_SOURCE_DIR"]], capture_output=True, text=True, env=env)
        check(r.returncode == 0, "pip install . : %s" % r.stderr[-500:])
        env2 = {k: v for k, v in os.environ.items() if k not in ("RAILRIDE_LIB", "PYTHONPATH")}
        env2["PYTHONPATH"] = tmp
        r = subprocess.run([sys.executable, "-c", "import railride, numpy as np; d = railride.Design('type1', "
                            "['primary.longitudinal_stiffness'], ['zeta_low']); print(railride.library()._name, "
                            "d.evaluate([50e6])[0])"], capture_output=True, text=True, env=env2, cwd=tmp)
        check(r.returncode == 0 and tmp in r.stdout and abs(float(r.stdout.split()[-1]) - ref["zeta_low"]) < 1e-13,
              "the installed package finds its own library: %s %s" % (r.stdout, r.stderr[-300:]))

# the binding's struct copies are checked against the library's layout at import: a
# copy that lost a field is refused
import ctypes  # noqa: E402


class _OldMode(ctypes.Structure):  # rr_mode without frame_roll_share
    _fields_ = [("re", ctypes.c_double), ("im", ctypes.c_double), ("freq_hz", ctypes.c_double),
                ("zeta", ctypes.c_double), ("energy", ctypes.c_double * 3), ("roll_share", ctypes.c_double),
                ("oscillatory", ctypes.c_int)]


try:
    railride._check_layout(railride.library(), {"rr_mode": _OldMode})
    check(False, "a stale struct copy is refused")
except railride.RailrideError as e:
    check("rr_mode" in str(e), "a stale struct copy is refused: %s" % e)
railride._check_layout(railride.library())  # the real copies pass
# contact geometry as numpy arrays: the same numbers as railride contact --json
P = os.path.join(os.environ["RR_SOURCE_DIR"], "profiles", "en15302")
cg = railride.contact(os.path.join(P, "RUIC519H.dat"), os.path.join(P, "SUIC519A.dat"), rail_gmp=-32.5,
                      radius=(460, 459), amplitudes=(1.0, 7.5, 0.1))
cj = json.loads(subprocess.run([cli, "contact", "--wheel", os.path.join(P, "RUIC519H.dat"), "--rail",
                                os.path.join(P, "SUIC519A.dat"), "--rail-gmp", "-32.5", "--radius", "460,459",
                                "--amplitudes", "1.0:7.5:0.1", "--json"], capture_output=True, check=True,
                               text=True).stdout)
nan = lambda v: np.array([float("nan") if x is None else x for x in v])  # JSON's null is NaN
close = lambda a, b: np.allclose(a, b, rtol=1e-13, atol=1e-13, equal_nan=True)  # cJSON prints 15 digits
check(close(cg["dr_mm"], cj["dr_mm"]) and close(cg["tan_gamma_e"], nan(cj["tan_gamma_e"]))
      and close(cg["y0_mm"], cj["y0_mm"]) and close(cg["tan_gamma_e_3mm"], cj["tan_gamma_e_3mm"]),
      "contact() equals contact --json")
check(abs(cg["y0_mm"] + 2.4939) < 1e-4 and abs(cg["tan_gamma_e_3mm"] - 0.26960) < 1e-5, "contact(): Annex E case E7")
# the wear study as numpy arrays: the numbers of railride wear --json, and Annex E's conicities
wini = os.path.join(tempfile.mkdtemp(), "wear.ini")
with open(wini, "w") as f:
    f.write("[vehicle]\nbase = type1\n[contact]\nrail = %s\ninclination = 0\ngauge_point = -32.5 mm\n"
            % os.path.join(P, "SUIC519A.dat"))
ww = [os.path.join(P, n) for n in ("RUIC519B.dat", "RUIC519I.dat")]
wp = railride.wear(ww, vehicle=wini, speed_kmh=300)
wj = json.loads(subprocess.run([cli, "wear", wini, "--wheels", ",".join(ww), "--speed", "300", "--json"],
                               capture_output=True, check=True, text=True).stdout)["profiles"]
check(close(wp["tan_gamma_e_3mm"], [p["tan_gamma_e_3mm"] for p in wj])
      and close(wp["tan_gamma_e"], [nan(p["tan_gamma_e"]) for p in wj])
      and close(wp["stability_index"], nan([p["stability_index"] for p in wj]))
      and close(wp["zeta_max"], [p["zeta_max"] for p in wj])
      and close(wp["critical_speed_kmh"], nan([p["critical_speed_kmh"] for p in wj]))
      and np.allclose(wp["sperling"], [p["sperling"] for p in wj], rtol=1e-12)
      and list(wp["stable"]) == [p["stable"] for p in wj], "wear() equals wear --json")
check(np.allclose(wp["tan_gamma_e_3mm"], [0.03228, 0.49305], atol=1e-5), "wear(): Annex E cases E2 and E8")
try:
    railride.wear(ww)  # the built-in vehicle names no rail
    check(False, "wear() without a rail is refused")
except railride.RailrideError as e:
    check("rail" in str(e), "wear() without a rail is refused: %s" % e)
# handles shared by threads: the same answers as one thread, and closing a
# handle another thread is using is an error, never a crash
import threading  # noqa: E402
shared = railride.Design("type1", ["yaw_damper.series_stiffness"], ["zeta_low", "index@300,0.3"], threads=1)
xs = np.linspace(5e6, 25e6, 24)[:, None]
want = shared.evaluate_batch(xs)
got = [None] * 4


def work(t):
    got[t] = np.vstack([shared.evaluate(x) for x in xs])


ts = [threading.Thread(target=work, args=(t,)) for t in range(4)]
for t in ts:
    t.start()
for t in ts:
    t.join(timeout=120)
check(all(g is not None and np.array_equal(g, want) for g in got), "a Design shared by 4 threads")
veh = railride.Vehicle("type2")
vref = {p: veh.modes(*p)["zeta"] for p in ((250, 0.05), (350, 0.17), (400, 0.4))}
vgot = {}


def vwork(p):
    for _ in range(5):
        vgot.setdefault(p, []).append(veh.modes(*p)["zeta"])


ts = [threading.Thread(target=vwork, args=(p,)) for p in vref]
for t in ts:
    t.start()
for t in ts:
    t.join(timeout=120)
check(all(np.array_equal(z, vref[p]) for p in vref for z in vgot.get(p, [None])), "a Vehicle shared by 3 threads")
big = np.tile(xs, (80, 1))  # ~0.7 s on one thread: the close comes 0.05 s in
closer = {}
busy = threading.Thread(target=lambda: closer.setdefault("f", shared.evaluate_batch(big)))
busy.start()
import time  # noqa: E402
time.sleep(0.05)
try:
    shared.close()
    closer["closed"] = True  # the evaluation had finished: a plain close
except railride.RailrideError as e:
    closer["refused"] = str(e)
busy.join(timeout=120)
check("refused" in closer and "in use" in closer["refused"], "close during use refused: %s" % closer)
check("f" in closer and closer["f"].shape == (big.shape[0], 2), "the evaluation in use finished")
shared.close()
try:
    shared.evaluate(xs[0])
    check(False, "a closed Design raises")
except railride.RailrideError:
    check(True, "a closed Design raises")

done("python")

#!/usr/bin/env bash
# The command line's contract: JSON keys, CSV headers, and exit status 2 with
# one line naming file, line and key on bad input.
set -u
RR=${RR_CLI:?RR_CLI must name the railride binary}
SRC=${RR_SOURCE_DIR:-..}
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Bad input: exit status 2, one line, naming what is wrong.
expect2() {  # expect2 NAME PATTERN CMD...
  local name=$1 pat=$2; shift 2
  "$@" > /dev/null 2> "$tmp/err"; local st=$?
  if [ $st -ne 2 ]; then bad "$name: exit $st (want 2)"; return; fi
  if [ "$(wc -l < "$tmp/err")" -ne 1 ]; then bad "$name: not one line: $(cat "$tmp/err")"; return; fi
  grep -q -- "$pat" "$tmp/err" && ok || bad "$name: '$(cat "$tmp/err")' lacks '$pat'"
}

# A missing helper or command must fail the suite, not pass silently.
command_not_found_handle() { bad "command not found: $1"; return 127; }

# JSON shape checks, in Python's json module (independent of cJSON).
json_check() {  # json_check NAME PYTHON-EXPRESSION < json
  if python3 -c "import json,math,sys; d=json.load(sys.stdin); sys.exit(0 if ($2) else 1)"; then ok; else bad "$1"; fi
}

"$RR" matrices --speed 350 --conicity 0.17 --json > "$tmp/m.json" || bad "matrices exit"
json_check "matrices keys" "len(d['dofs'])==17 and d['dofs'][0]=='y_c' and d['dofs'][16]=='psi_w4' and all(len(d[k])==17 and all(len(r)==17 for r in d[k]) for k in 'MCK') and len(d['B'])==17 and len(d['B'][0])==4 and len(d['maxwell'])==6 and all(set(x)>={'name','J','k','c'} and len(x['J'])==17 for x in d['maxwell']) and len(d['A'])==40 and len(d['A'][0])==40" < "$tmp/m.json"

"$RR" modes --speed 350 --conicity 0.17 --json > "$tmp/modes.json" || bad "modes exit"
json_check "modes keys" "isinstance(d['stability_index'],float) and all(set(m)>={'freq_hz','real','imag','stability_index','energy'} and set(m['energy'])=={'carbody','frames','wheelsets'} and m['imag']>0 for m in d['modes']) and [m['freq_hz'] for m in d['modes']]==sorted(m['freq_hz'] for m in d['modes'])" < "$tmp/modes.json"
json_check "modes index is the max over in_index" "abs(d['stability_index']-max(m['stability_index'] for m in d['modes'] if m['in_index']))<1e-15" < "$tmp/modes.json"
json_check "energy shares sum to 1" "all(abs(sum(m['energy'].values())-1)<1e-12 for m in d['modes'])" < "$tmp/modes.json"

json_check "modes: roll share, name, hunting-related" "all(0<=m['roll_share']<=1 and isinstance(m['name'],str) and m['name'] and isinstance(m['hunting_related'],bool) for m in d['modes']) and all(not m['in_index'] for m in d['modes'] if m['roll_share']>=0.5) and d['stable'] is True and d['r_max']==0.5" < "$tmp/modes.json"
"$RR" modes --speed 350 --conicity 2 > "$tmp/modes2.txt" || bad "modes at conicity 2 exit"
grep -q "^verdict: UNSTABLE" "$tmp/modes2.txt" && ok || bad "modes at conicity 2: verdict not unstable"
"$RR" modes --speed 350 --conicity 0.17 --rmax 1 --wmin 0 --json > "$tmp/modes3.json" || bad "modes --rmax exit"
json_check "--rmax 1 --wmin 0: the index over every mode in the band" "abs(d['stability_index']-max(m['stability_index'] for m in d['modes'] if m['freq_hz']<=d['fmax_hz']))<1e-15 and abs(d['fmax_hz']-10.8872)<1e-4 and d['fmax_rule']=='kinematic'" < "$tmp/modes3.json"
"$RR" critical-speed --conicity 0.6 --json > "$tmp/c6.json" || bad "critical 0.6 exit"
json_check "critical speed over any mode" "abs(d['critical_speed_kmh']-422.1)<0.05 and 10<d['mode']['freq_hz']<10.2 and d['mode']['hunting_related'] and 'roll_share' in d['mode']" < "$tmp/c6.json"
"$RR" critical-speed --conicity 0.6 --index-modes --fmax 10 --json > "$tmp/c6i.json" || bad "critical --index-modes exit"
json_check "critical speed, index modes below a fixed 10 Hz" "d['critical_speed_kmh'] is None and d['stable_to_range_end']" < "$tmp/c6i.json"
"$RR" critical-speed --conicity 0.6 --index-modes --json > "$tmp/c6k.json" || bad "critical --index-modes exit"
json_check "critical speed, index modes with the band edge at f_K" "abs(d['critical_speed_kmh']-422.1)<0.05" < "$tmp/c6k.json"
"$RR" sweep --x "yaw_damper.damping=4000 kN.s/m:4000 kN.s/m:1" --y "yaw_damper.series_stiffness=10 MN/m:10 MN/m:1" --objective index@350,0.17 --rmax 1 --wmin 0 --fmax 20 > "$tmp/swr.csv" || bad "sweep --rmax exit"
"$RR" modes --speed 350 --conicity 0.17 --rmax 1 --wmin 0 --fmax 20 --json > "$tmp/modes4.json"
python3 -c "
import csv, json, sys
r = list(csv.DictReader(open('$tmp/swr.csv'))); d = json.load(open('$tmp/modes4.json'))
sys.exit(0 if abs(float(r[0]['index@350,0.17']) - d['stability_index']) < 1e-9 else 1)" && ok || bad "sweep --rmax/--wmin/--fmax reach the objective value"

"$RR" robust --json > "$tmp/r.json" || bad "robust exit"
json_check "robust keys" "all(isinstance(d[k],float) for k in ('zeta_low','zeta_high','std_zeta'))" < "$tmp/r.json"
"$RR" critical-speed --conicity 0.4 --json > "$tmp/c.json" || bad "critical exit"
json_check "critical keys" "'critical_speed_kmh' in d and (d['critical_speed_kmh'] is None or 10<=d['critical_speed_kmh']<=600)" < "$tmp/c.json"
"$RR" critical-speed --conicity 0.05 --vmax 300 --json > "$tmp/c2.json" || bad "critical exit 2"
json_check "stable to range end" "d['critical_speed_kmh'] is None and d['stable_to_range_end']" < "$tmp/c2.json"

"$RR" sweep --x conicity=0.2:0.6:3 --objective sperling@600 > "$tmp/sws.csv" 2> /dev/null || bad "sweep ride exit"
[ "$(cat "$tmp/sws.csv" | tr '\n' ' ')" = "conicity,sperling@600,stable 0.2,1.799415917,1 0.4,,0 0.6,,0 " ] && ok ||
  bad "sweep: a ride objective undefined where unstable, with the verdict: $(cat "$tmp/sws.csv" | tr '\n' ' ')"
"$RR" sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:3" --objective "critical_speed@0.17;vmax=700" > "$tmp/swc.csv" || bad "sweep critical exit"
head -1 "$tmp/swc.csv" | grep -q ',at_range_end$' && awk -F, 'NR > 1 && $2 == 700 && $NF != 1 {b++} END {exit b}' "$tmp/swc.csv" &&
  grep -q ',700,.*,1$' "$tmp/swc.csv" && ok || bad "sweep: a critical speed at vmax flagged at_range_end"
"$RR" locus --over speed --range 100:400:4 > "$tmp/l.csv" || bad "locus exit"
head -1 "$tmp/l.csv" | grep -qx 'branch,speed_kmh,conicity,freq_hz,real_per_s,imag_rad_per_s,stability_index,mac,e_carbody,e_frames,e_wheelsets,roll_share,hunting_related,frame_roll_share' && ok || bad "locus header"
"$RR" map --speeds 200:300:2 --conicities 0.1:0.2:2 > "$tmp/map.csv" || bad "map exit"
[ "$(wc -l < "$tmp/map.csv")" -eq 5 ] && head -1 "$tmp/map.csv" | grep -qx 'speed_kmh,conicity,stability_index,index_freq_hz,zeta_max,stable,index_source,fmax_hz' && ok || bad "map shape"
# map --shares: the same index, and the hunting mode's shares as modes reports them
"$RR" map --speeds 200:300:2 --conicities 0.1:0.2:2 --shares > "$tmp/maps.csv" || bad "map --shares exit"
"$RR" modes --speed 300 --conicity 0.2 --json > "$tmp/maps-modes.json" || bad "modes exit"
python3 - "$tmp/map.csv" "$tmp/maps.csv" "$tmp/maps-modes.json" <<'PY' && ok || bad "map --shares"
import csv, json, sys
plain, shares = (list(csv.DictReader(open(f))) for f in sys.argv[1:3])
assert len(shares) == len(plain) == 4
for p, s in zip(plain, shares):
    for k in p:
        assert p[k] == s[k] if k in ("stable", "index_source") else abs(float(p[k]) - float(s[k])) <= 1e-9 * max(1, abs(float(p[k]))), (k, p[k], s[k])
    e = [float(s["hunting_e_" + g]) for g in ("carbody", "frames", "wheelsets")]
    assert abs(sum(e) - 1) < 1e-9 and min(e) >= 0, e
m = json.load(open(sys.argv[3]))
assert m["index_source"] == "hunting"
hunt = [md for md in m["modes"] if md["name"] == m["index_mode"]]
assert len(hunt) == 1, m["index_mode"]
hunt = hunt[0]
last = shares[-1]
assert (last["speed_kmh"], last["conicity"]) == ("300", "0.2")
assert abs(float(last["hunting_freq_hz"]) - hunt["freq_hz"]) < 1e-9 * hunt["freq_hz"]
for g, name in enumerate(("carbody", "frames", "wheelsets")):
    assert abs(float(last["hunting_e_" + name]) - hunt["energy"][name]) < 1e-9, (name, last, hunt["energy"])
PY
"$RR" damper --freqs 0.1:10:5 > "$tmp/d.csv" || bad "damper exit"
grep -q '^freq_hz,k_series_n_per_m,storage_n_per_m,loss_n_per_m,eq_damping_n_s_per_m,dissipation$' "$tmp/d.csv" && ok || bad "damper header"
# --k K1,K2: one curve per stiffness, the rows of the single runs in turn
"$RR" damper --freqs 0.1:10:5 --k "5 MN/m,2e7" > "$tmp/dk.csv" 2> /dev/null &&
  "$RR" damper --freqs 0.1:10:5 --k 5e6 > "$tmp/dk1.csv" 2> /dev/null &&
  "$RR" damper --freqs 0.1:10:5 --k 20e6 | tail -n +2 >> "$tmp/dk1.csv" &&
  cmp -s "$tmp/dk.csv" "$tmp/dk1.csv" && ok || bad "damper --k list"
[ "$("$RR" damper --freqs 1:2:2 --k 5e6,1e7,2e7 --json | grep -c '"omega_opt"')" -eq 3 ] && ok || bad "damper --k list JSON curves"
# pareto: four separated groups of a front found whole (quoted objective names, an infeasible
# design left out); the JSON's centres the means of their members, the CSV the file's rows
python3 - "$tmp/front.csv" <<'PY'
import sys
rows = ['yaw_damper.damping_n_s_per_m,"index@350,0.17",zeta_high,feasible,violation']
centres = [(-0.3, 0.1), (-0.1, -0.3), (0.05, -0.05), (-0.2, 0.05)]
for i in range(24):
    g, j = i % 4, i // 4
    a, b = centres[g]
    rows.append("%g,%.6f,%.6f,1,0" % (1e5 * (i + 1), a + 0.004 * (j - 2.5), b + 0.003 * ((j * 5) % 6 - 2.5)))
rows.append("1e6,-0.9,-0.9,0,0.5")
open(sys.argv[1], "w").write("\n".join(rows) + "\n")
PY
"$RR" pareto "$tmp/front.csv" --csv > "$tmp/front-cl.csv" && "$RR" pareto "$tmp/front.csv" --json > "$tmp/front.json" &&
python3 - "$tmp/front.csv" "$tmp/front-cl.csv" "$tmp/front.json" <<'PY' && ok || bad "pareto clusters"
import csv, json, sys
src = open(sys.argv[1]).read().splitlines()
out = list(csv.reader(open(sys.argv[2])))
js = json.load(open(sys.argv[3]))
assert out[0][-1] == "cluster" and out[0][1] == "index@350,0.17", out[0]
assert [",".join(r[:-1]) for r in out[1:]] == src[1:], "rows as written"
lab = [r[-1] for r in out[1:]]
assert lab[-1] == "" and js["labels"][-1] is None, "the infeasible design is not clustered"
want = {0: "A", 3: "B", 1: "C", 2: "D"}  # named by ascending first objective: -0.3, -0.2, -0.1, 0.05
assert all(lab[i] == want[i % 4] for i in range(24)), lab
for c in js["clusters"]:
    mem = [r for r in out[1:] if r[-1] == c["name"]]
    assert c["designs"] == len(mem) == 6
    for k, col in (("index@350,0.17", 1), ("zeta_high", 2)):
        assert abs(c["centre"][k] - sum(float(r[col]) for r in mem) / 6) < 1e-12, (c, k)
    v = c["variables"]["yaw_damper.damping_n_s_per_m"]
    assert v["min"] == min(float(r[0]) for r in mem) and v["max"] == max(float(r[0]) for r in mem)
PY
printf 'a.b_n,zeta_low\n1,0.1\n2,x\n' > "$tmp/front-bad.csv"
expect2 "pareto: a bad number names file and line" "front-bad.csv:3: column 'zeta_low'" "$RR" pareto "$tmp/front-bad.csv"
head -2 "$tmp/front-bad.csv" > "$tmp/front-one.csv"
expect2 "pareto: more clusters than designs" "5 clusters asked of 1" "$RR" pareto "$tmp/front-one.csv" --clusters 5
expect2 "pareto: no file" "cannot read" "$RR" pareto "$tmp/none.csv"
# the help names the columns the run writes, and compare's help one default for VEHICLE
[ "$("$RR" damper --help | sed -n 's/^CSV columns: //p')" = "$(head -1 "$tmp/d.csv")" ] && ok || bad "damper --help columns"
"$RR" compare --help > "$tmp/cmph.txt" && [ "$(grep -c '^  VEHICLE' "$tmp/cmph.txt")" -eq 1 ] && grep -q 'default both' "$tmp/cmph.txt" && ok || bad "compare --help VEHICLE default"
"$RR" summary "$SRC/examples/type2.ini" > "$tmp/s.txt" || bad "summary exit"
grep -q "vehicle stability index" "$tmp/s.txt" && ok || bad "summary text"

"$RR" ride --speed 350 --conicity 0.05,0.2 --json --psd "$tmp/psd.csv" > "$tmp/ride.json" || bad "ride exit"
json_check "ride keys" "d['spectrum']=='wuhan-guangzhou' and [r['conicity'] for r in d['results']]==[0.05,0.2] and all(len(r['points'])==3 and all(set(p)>={'x','rms','sperling','sperling_gb','wd_rms'} for p in r['points']) for r in d['results'])" < "$tmp/ride.json"
json_check "ride methods stated" "all(k in d['methods'] for k in ('sperling','sperling_gb','wd_rms'))" < "$tmp/ride.json"
head -1 "$tmp/psd.csv" | grep -q '^f_hz,psd_c0.05_x8.6875m_m2s-4_per_hz,psd_c0.05_x0m_m2s-4_per_hz,psd_c0.05_x-8.6875m_m2s-4_per_hz,psd_c0.2_x8.6875m_m2s-4_per_hz,.*,sperling_weight$' && [ "$(wc -l < "$tmp/psd.csv")" -eq 401 ] && ok || bad "psd csv"
# the PSD file integrates to the reported RMS (trapezoid), checked in Python
python3 - "$tmp/psd.csv" "$tmp/ride.json" <<'PY' && ok || bad "psd csv integrates to rms"
import csv, json, sys
rows = list(csv.reader(open(sys.argv[1])))
d = json.load(open(sys.argv[2]))
f = [float(r[0]) for r in rows[1:]]
g = [float(r[1]) for r in rows[1:]]
var = sum(0.5 * (g[i] + g[i + 1]) * (f[i + 1] - f[i]) for i in range(len(f) - 1))
sys.exit(0 if abs(var ** 0.5 - d['results'][0]['points'][0]['rms']) < 1e-6 * var ** 0.5 else 1)
PY
"$RR" ride type2 --speed 300 --conicity 0.3 --sdf paper --json > "$tmp/rm.json" || bad "ride modal"
"$RR" ride type2 --speed 300 --conicity 0.3 --sdf paper --method direct --json > "$tmp/rd.json" || bad "ride direct"
python3 -c "
import json,sys
a=json.load(open('$tmp/rm.json'))['results'][0]['points']; b=json.load(open('$tmp/rd.json'))['results'][0]['points']
sys.exit(0 if all(abs(p[k]-q[k])<=1e-9*abs(q[k]) for p,q in zip(a,b) for k in ('rms','sperling','sperling_gb','wd_rms')) else 1)" && ok || bad "ride modal vs direct"
"$RR" frf --speed 350 --conicity 0.2 --band 1:10:3 > "$tmp/frf.csv" || bad "frf exit"
[ "$(head -1 "$tmp/frf.csv")" = "f_hz,x_m,input,re_per_s2,im_per_s2,magnitude_per_s2,phase_deg" ] && [ "$(wc -l < "$tmp/frf.csv")" -eq 46 ] && ok || bad "frf csv shape"
"$RR" compare --conicities 0.1:0.3:2 --json > "$tmp/cmp.json" || bad "compare exit"
json_check "compare rows" "len(d['rows'])==4 and {r['vehicle'] for r in d['rows']}=={'type1','type2'} and all(set(r)>={'conicity','stability_index_const','stability_index_sdf','sperling_const','sperling_sdf','n_mv_const','n_mv_sdf'} and 0<r['n_mv_sdf']<5 for r in d['rows'])" < "$tmp/cmp.json"
"$RR" summary --json > "$tmp/sum.json" || bad "summary json"
json_check "summary ride table" "len(d['ride'])==6 and {r['yaw_series'] for r in d['ride']}=={'constant','sdf'}" < "$tmp/sum.json"
json_check "summary vertical and EN 12299" "len(d['vertical']['points'])==3 and all(abs(p['n_mv']-6*math.hypot(p['wd_p95'],p['wb_p95']))<1e-12 for p in d['vertical']['points']) and d['vertical']['spectrum']=='tbt3352-vertical'" < "$tmp/sum.json"

"$RR" validate --speed 350 --conicity 0.2 --duration 32 --fs 128 --nseg 512 --json --psd "$tmp/v.csv" > "$tmp/val.json" || bad "validate exit"
json_check "validate verdict" "d['verdict']=='PASS' and d['tolerances']['z']==4 and 0<d['tolerances']['sperling_gb_relative']<0.2" < "$tmp/val.json"
"$RR" validate --speed 350 --conicity 0.2 --duration 32 --fs 128 --nseg 512 --track-amplitudes fixed --json > "$tmp/valf.json" || bad "validate fixed exit"
json_check "validate, fixed amplitudes: deterministic agreement" "d['track_amplitudes']=='fixed' and abs(d['rms_time']/d['rms_pem']-1)<2e-3 and abs(d['sperling_time']/d['sperling_pem']-1)<1e-3" < "$tmp/valf.json"
"$RR" critical-speed --conicity 0.05,0.4,0.6 --json > "$tmp/crits.json" || bad "critical-speed list exit"
json_check "critical-speed over a conicity list" "[r['conicity'] for r in d['results']]==[0.05,0.4,0.6] and d['results'][0]['critical_speed_kmh'] is None and abs(d['results'][1]['critical_speed_kmh']-524.7)<0.05 and abs(d['results'][2]['critical_speed_kmh']-422.1)<0.05" < "$tmp/crits.json"
json_check "validate keys" "all(isinstance(d[k],float) for k in ('sperling_pem','sperling_time','rms_pem','rms_time','psd_band_error_max')) and len(d['points'])==3 and all(abs(p['rms_z'])<4 and abs(p['sperling_z'])<4 for p in d['points']) and d['psd_band_z_max']<4" < "$tmp/val.json"
head -1 "$tmp/v.csv" | grep -q '^f_hz,welch_x8.6875m_m2s-4_per_hz,welch_x0m_m2s-4_per_hz,welch_x-8.6875m_m2s-4_per_hz,pem_x8.6875m_m2s-4_per_hz,.*,welch_sigma_rel$' && ok || bad "validate psd csv"
expect2 "validate paper mode" "paper-mode SDF has no time-domain form" "$RR" validate --speed 300 --conicity 0.2 --sdf paper --duration 16
printf '[vehicle]\nbase = type1\n[yaw_damper]\ndamping = 0\n[lateral_damper]\ndamping = 0\n' > "$tmp/nod.ini"
expect2 "validate unstable vehicle" "unstable at 300 km/h" "$RR" validate "$tmp/nod.ini" --speed 300 --conicity 0.2 --duration 16 --nseg 256
"$RR" ride "$tmp/nod.ini" --speed 300 --conicity 0.2 > /dev/null 2> "$tmp/warn" && grep -q "warning: unstable" "$tmp/warn" && ok || bad "ride warns when unstable"
expect2 "validate duration" "--duration" "$RR" validate --speed 300 --conicity 0.2 --duration 0
expect2 "validate seed" "--seed" "$RR" validate --speed 300 --conicity 0.2 --seed -4

"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 12 --generations 2 --threads 2 --output "$tmp/po" --progress > "$tmp/po.txt" 2> "$tmp/po.err" || bad "optimise exit"
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 12 --generations 2 --threads 2 --output "$tmp/po2" > /dev/null 2> "$tmp/po2.err" && [ ! -s "$tmp/po2.err" ] && ok || bad "optimise: no progress when stderr is not a terminal"
head -1 "$tmp/po-pareto.csv" | grep -qx 'primary.longitudinal_stiffness_n_per_m,lateral_damper.damping_n_s_per_m,yaw_damper.damping_n_s_per_m,yaw_damper.series_stiffness_n_per_m,zeta_low,zeta_high,std_zeta' && [ "$(wc -l < "$tmp/po-pareto.csv")" -ge 2 ] && ok || bad "optimise pareto csv"
grep -q "evals/s" "$tmp/po.err" && grep -q "hypervolume" "$tmp/po.err" && grep -q "ETA" "$tmp/po.err" && ok || bad "optimise progress"
# the Pareto rows are mutually non-dominated and within the bounds (checked in Python)
python3 - "$tmp/po-pareto.csv" <<'PY' && ok || bad "pareto rows non-dominated and in bounds"
import csv, sys
rows = [list(map(float, r)) for r in list(csv.reader(open(sys.argv[1])))[1:]]
lo, hi = [10e6, 5e3, 100e3, 1e6], [120e6, 60e3, 4000e3, 30e6]
ok = all(lo[j] <= r[j] <= hi[j] for r in rows for j in range(4))
F = [r[4:] for r in rows]
dom = lambda a, b: all(x <= y for x, y in zip(a, b)) and any(x < y for x, y in zip(a, b))
ok = ok and not any(dom(a, b) for a in F for b in F)
sys.exit(0 if ok else 1)
PY
"$RR" sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:3" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:2" --objective index@350,0.17 > "$tmp/sw.csv" || bad "sweep exit"
[ "$(head -1 "$tmp/sw.csv")" = 'yaw_damper.damping_n_s_per_m,yaw_damper.series_stiffness_n_per_m,"index@350,0.17",mode_freq_hz,k_opt_n_per_m,fmax_hz' ] && [ "$(wc -l < "$tmp/sw.csv")" -eq 7 ] && ok || bad "sweep csv"
printf '[problem]\npopulation = 7\n[variables]\nprimary.longitudinal_stiffness = 10 kN/mm .. 120 kN/mm\n[objectives]\nobjective = zeta_low minimize\n' > "$tmp/p1.ini"
expect2 "odd population" "p1.ini:2: \[problem\] population" "$RR" optimise "$tmp/p1.ini"
printf '[problem]\n[variables]\nprimary.stiffness = 1 .. 2\n[objectives]\nobjective = zeta_low minimize\n' > "$tmp/p2.ini"
expect2 "bad variable key" "p2.ini:3: \[variables\] primary.stiffness" "$RR" optimise "$tmp/p2.ini"
printf '[problem]\n[variables]\nprimary.longitudinal_stiffness = 10 kg .. 20 kg\n[objectives]\nobjective = zeta_low minimize\n' > "$tmp/p3.ini"
expect2 "variable unit" "p3.ini:3: \[variables\] primary.longitudinal_stiffness" "$RR" optimise "$tmp/p3.ini"
expect2 "sweep key" "--x" "$RR" sweep --x nope.key=1:2:3 --y yaw_damper.damping=1:2:2 --objective zeta_low

for c in summary matrices modes robust critical-speed locus map damper ride frf compare validate optimise sweep; do
  "$RR" $c --help > /dev/null && ok || bad "$c --help"
done

printf '[vehicle]\nbase = type1\n[primary]\nlateral_stiffness = 5 kN\n' > "$tmp/v1.ini"
expect2 "wrong unit" "v1.ini:4: \[primary\] lateral_stiffness" "$RR" modes "$tmp/v1.ini" --speed 300 --conicity 0.2
printf '[vehicle]\nbase = type1\n[carbody]\nmas = 5\n' > "$tmp/v2.ini"
expect2 "unknown key" "v2.ini:4: \[carbody\] mas: unknown key" "$RR" robust "$tmp/v2.ini"
printf '[vehicle]\nbase = type1\n[frame]\nmass = -2328 kg\n' > "$tmp/v3.ini"
expect2 "negative mass" "v3.ini:4: \[frame\] mass" "$RR" summary "$tmp/v3.ini"
printf '[vehicle]\nbase = type1\n[wheelset]\nyaw_inertia = nan\n' > "$tmp/v4.ini"
expect2 "NaN" "v4.ini:4: \[wheelset\] yaw_inertia" "$RR" summary "$tmp/v4.ini"
expect2 "missing file" "nofile.ini" "$RR" modes "$tmp/nofile.ini" --speed 300 --conicity 0.2
expect2 "zero speed" "--speed" "$RR" modes --speed 0 --conicity 0.2
expect2 "NaN speed" "--speed" "$RR" modes --speed nan --conicity 0.2
expect2 "negative conicity" "--conicity" "$RR" modes --speed 300 --conicity -0.1
expect2 "speed unit" "--speed" "$RR" modes --speed "300 kg" --conicity 0.1
expect2 "missing speed" "--speed is required" "$RR" modes --conicity 0.1
expect2 "unknown option" "unknown option" "$RR" modes --sped 300
expect2 "unknown command" "unknown command" "$RR" frobnicate
expect2 "bad range" "--range" "$RR" locus --range 1:2
printf 'f_hz,k\n1,2e6\n0.5,3e6\n' > "$tmp/t.csv"
printf '[vehicle]\nbase = type1\n[yaw_damper]\nsdf = paper\nsdf_table = t.csv\n' > "$tmp/v5.ini"
expect2 "malformed table" "frequencies must increase" "$RR" modes "$tmp/v5.ini" --speed 300 --conicity 0.2

expect2 "unknown spectrum" "unknown spectrum 'nope'" "$RR" ride --speed 300 --conicity 0.2 --spectrum nope
printf 'direction = lateral\nform = powerlaw\nfreq_unit = 1/m\npsd_unit = mm^2/(1/m)\nsided = one\nvalid = 0.01 0.5\nsegment = 0.01 0.5 1 x\n' > "$tmp/sp.txt"
expect2 "malformed spectrum" "sp.txt:7: segment" "$RR" ride --speed 300 --conicity 0.2 --spectrum "$tmp/sp.txt"
expect2 "conicity list where one value" "one value expected" "$RR" modes --speed 300 --conicity 0.1,0.2
expect2 "bad band" "--band" "$RR" ride --speed 300 --conicity 0.2 --band 10:1:5

# The nonlinear model: simulate's CSV, bifurcation's JSON against critical-speed.
"$RR" simulate --speed 350 --profile worn --duration 2 --fs 100 > "$tmp/sim.csv" 2> "$tmp/sim.err" || bad "simulate exit"
python3 - "$tmp/sim.csv" "$tmp/sim.err" <<'PY' && ok || bad "simulate csv"
import csv, math, sys
rows = list(csv.reader(open(sys.argv[1])))
head = rows[0]
assert head[0] == 't_s' and head[1] == 'y_c_m' and head[2] == 'psi_c_rad' and len(head) == 1 + 17 + 16, head
assert head[-4:] == ['yt_w4_m', 'Fy_w4_N', 'Mz_w4_Nm', 'flange_w4_N'], head[-4:]
assert len(rows) == 202 and all(math.isfinite(float(x)) for r in rows[1:] for x in r)
assert abs(float(rows[1][head.index('y_w1_m')]) - 5e-3) < 1e-15      # the default disturbance
assert not any(l.startswith('#') for l in open(sys.argv[1]))              # plain CSV
assert 'friction 0.3' in open(sys.argv[2]).read()                          # the assumptions on stderr
PY
printf 'distance_m,alignment_m\n' > "$tmp/track.csv"
python3 -c "import math; [print(f'{0.25*i},{1e-3*math.sin(2*math.pi*0.25*i/30)}') for i in range(4000)]" >> "$tmp/track.csv"
"$RR" simulate --speed 300 --profile worn --duration 5 --fs 100 --track "$tmp/track.csv" > "$tmp/simt.csv" || bad "simulate --track exit"
python3 - "$tmp/simt.csv" <<'PY' && ok || bad "simulate --track: each wheelset reads the record at its position"
import csv, math, sys
rows = list(csv.reader(open(sys.argv[1])))
h = rows[0]; r = rows[101]; v = 300 / 3.6; t = float(r[0])
# the last wheelset starts at the record's start; the first is 2 (L + b) = 19.875 m ahead
for w, dx in ((4, 0.0), (1, 19.875)):
    want = 1e-3 * math.sin(2 * math.pi * (v * t + dx) / 30)
    assert abs(float(r[h.index(f'yt_w{w}_m')]) - want) < 2e-6, (w, r[h.index(f'yt_w{w}_m')], want)
PY
"$RR" simulate --speed 300 --profile worn --duration 3 --spectrum wuhan-guangzhou --seed 7 > "$tmp/sims.csv" || bad "simulate --spectrum exit"
# simulate's output choices: --every and --columns pick rows and columns of the full run,
# --accelerations agree with the displacements' second differences
"$RR" simulate --speed 300 --profile worn --duration 1 --fs 2000 --accelerations > "$tmp/sima.csv" 2> /dev/null || bad "simulate --accelerations exit"
"$RR" simulate --speed 300 --profile worn --duration 1 --fs 2000 --every 50 --columns y_w1_m,y_c_acc_m_s2,Fy_w1_N \
  > "$tmp/simc.csv" 2> /dev/null || bad "simulate --every --columns exit"
python3 - "$tmp/sima.csv" "$tmp/simc.csv" <<'PY' && ok || bad "simulate --every, --columns, --accelerations"
import csv, sys
full = list(csv.DictReader(open(sys.argv[1])))
pick = list(csv.reader(open(sys.argv[2])))
assert pick[0] == ["t_s", "y_w1_m", "y_c_acc_m_s2", "Fy_w1_N"], pick[0]
assert len(pick) - 1 == (len(full) + 49) // 50, (len(pick), len(full))
for row, k in zip(pick[1:], range(0, len(full), 50)):
    assert row == [full[k][c] for c in pick[0]], (k, row)
dt = float(full[1]["t_s"]) - float(full[0]["t_s"])
for dof in ("y_c", "y_w1"):
    y = [float(r[dof + "_m"]) for r in full]
    a = [float(r[dof + "_acc_m_s2"]) for r in full]
    amax = max(abs(x) for x in a[1:])
    worst = max(abs((y[k + 1] - 2 * y[k] + y[k - 1]) / dt ** 2 - a[k]) for k in range(1, len(y) - 1))
    assert worst <= 1e-2 * amax, (dof, worst, amax)
PY
"$RR" simulate --speed 300 --profile worn --duration 1 --columns y_w1,nope > /dev/null 2> "$tmp/simc.err"; rc=$?
[ $rc -eq 2 ] && grep -q "no column 'y_w1'" "$tmp/simc.err" && ok || bad "simulate --columns: an unknown name is refused ($rc)"
# Ctrl-C: the samples done are written, exit 130
# (a track input keeps the integrator busy: unstopped, this run takes minutes)
timeout --preserve-status -s INT 1 "$RR" simulate --speed 300 --profile worn --duration 10000 --fs 10 \
  --spectrum wuhan-guangzhou > "$tmp/simstop.csv" 2> "$tmp/simstop.err"; rc=$?
python3 - "$tmp/simstop.csv" <<'PY' && [ $rc -eq 130 ] && grep -q "stopped by a signal" "$tmp/simstop.err" && ok || bad "simulate stopped by SIGINT ($rc)"
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
assert rows[0][0] == "t_s" and 2 <= len(rows) < 100001, len(rows)
assert all(abs(float(r[0]) - k / 10) < 1e-9 for k, r in enumerate(rows[1:])), "times in order from 0"
PY
# bifurcation stopped by SIGINT: what is found is written, exit 130 (both methods).
# The signal comes at 40% of an unstopped run's time, measured here, so that it lands
# mid-run on a machine of any speed; the stopped run must agree with the full one.
bif_stop() {  # OUT ARGS...: a full run to OUT.full, then one stopped to OUT
  local out=$1 t0 t1 delay; shift
  t0=$(date +%s.%N)
  (cd "$RR_SOURCE_DIR/examples" && "$RR" bifurcation "$@") > "$out.full" 2> /dev/null
  t1=$(date +%s.%N)
  delay=$(python3 -c "import sys; print(f'{0.4 * (float(sys.argv[2]) - float(sys.argv[1])):.3f}')" "$t0" "$t1")
  (cd "$RR_SOURCE_DIR/examples" && timeout --preserve-status -s INT "$delay" "$RR" bifurcation "$@") \
    > "$out" 2> "$out.err"
}
bif_stop "$tmp/bifstop.json" type2.ini --profile worn --json; rc=$?
python3 - "$tmp/bifstop.json" <<'PY' && [ $rc -eq 130 ] && ok || bad "bifurcation stopped by SIGINT ($rc)"
import json, sys
d = json.load(open(sys.argv[1]))
full = json.load(open(sys.argv[1] + ".full"))
assert d["branch_end"] == "stopped by a signal" and len(d["branch"]) >= 1, (d["branch_end"], len(d["branch"]))
assert len(d["branch"]) < len(full["branch"]), (len(d["branch"]), len(full["branch"]))
assert d["branch"] == full["branch"][:len(d["branch"])], "the branch so far is the full branch's start"
PY
bif_stop "$tmp/scanstop.csv" type2.ini --profile worn --method scan --speeds 100:200 --csv; rc=$?
python3 - "$tmp/scanstop.csv" <<'PY' && [ $rc -eq 130 ] && grep -q "runs written" "$tmp/scanstop.csv.err" && ok || bad "bifurcation --method scan stopped by SIGINT ($rc)"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
full = list(csv.DictReader(open(sys.argv[1] + ".full")))
assert len(rows) == len(full) == 42 and rows[0]["sweep"] == "up", (len(rows), len(full))
done = [r for r in rows if r["amplitude_m"] != ""]
assert 1 <= len(done) < 42, len(done)
assert all(r == f for r, f in zip(done, full)), "the runs done are the full scan's first runs"
PY
"$RR" bifurcation --profile worn --speeds 100:560 --json > "$tmp/bif.json" || bad "bifurcation exit"
"$RR" critical-speed --conicity 0.375 --json > "$tmp/crit.json" || bad "critical-speed exit"
python3 - "$tmp/bif.json" "$tmp/crit.json" <<'PY' && ok || bad "bifurcation json"
import json, sys
d = json.load(open(sys.argv[1])); c = json.load(open(sys.argv[2]))
assert d['profile'] == 'worn' and d['type'] == 'supercritical' and d['method'] == 'continuation'
assert abs(d['linear_critical_speed_kmh'] - c['critical_speed_kmh']) < 2e-3   # both bisected to 1e-3 km/h
assert abs(d['hopf_speed_from_branch_kmh'] - c['critical_speed_kmh']) < 0.1
assert d['nonlinear_critical_speed_kmh'] == d['linear_critical_speed_kmh']
a = d['assumptions']
assert a['friction'] == 0.3 and a['flange_clearance_m'] == 0.008 and a['flange_stiffness_n_per_m'] == 5e8 and '0.375' in a['conicity']
b = d['branch']
assert len(b) >= 5 and all(set(p) >= {'speed_kmh', 'amplitude_m', 'frequency_hz', 'stable', 'max_floquet_modulus'} for p in b)
assert all(p['residual'] <= 1e-8 for p in b) and all(p['stable'] == (p['max_floquet_modulus'] < 1) for p in b)
assert max(p['speed_kmh'] for p in b) <= 560 + 10
PY
"$RR" bifurcation --profile worn --method scan --speeds 530:560 --step 15 --settle 4 --json > "$tmp/scan.json" || bad "scan exit"
json_check "bifurcation scan" "d['method']=='scan' and len(d['branch'])==6 and [p['sweep'] for p in d['branch']]==['up']*3+['down']*3 and d['branch'][0]['amplitude_m']==0 and d['branch'][2]['amplitude_m']>3e-4 and d['type']=='supercritical'" < "$tmp/scan.json"
"$RR" bifurcation --profile "$SRC/examples/tread-worn.csv" --speeds 100:545 --csv > "$tmp/bif.csv" || bad "bifurcation csv"
head -1 "$tmp/bif.csv" | grep -q "^speed_kmh,amplitude_m,frequency_hz,stable,max_floquet_modulus,symmetric,residual$" && ok || bad "bifurcation csv header"

# Long runs: Ctrl-C stops after the generation in progress and writes its front
timeout -s INT --preserve-status 3 "$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 100000 \
  --threads 1 --output "$tmp/int" > "$tmp/int.out" 2>&1; st=$?
[ $st -eq 130 ] && grep -q "stopped by a signal after generation" "$tmp/int.out" && [ "$(wc -l < "$tmp/int-pareto.csv")" -gt 1 ] \
  && [ "$(wc -l < "$tmp/int-history.csv")" -gt 1 ] && ok || bad "optimise interrupted: exit $st, $(tail -2 "$tmp/int.out")"
head -1 "$tmp/int-history.csv" | grep -q '^generation,evaluations,seconds,front_size,hypervolume$' && ok || bad "history header"
# locus, validate, summary: progress on request; a stopped locus writes the points done
"$RR" summary --progress 2> "$tmp/sp.err" > /dev/null && grep -q "summary: 12/12 in" "$tmp/sp.err" && ok || bad "summary --progress"
"$RR" validate --speed 350 --conicity 0.2 --duration 32 --fs 128 --nseg 512 --progress 2> "$tmp/vp.err" > /dev/null \
  && grep -q "validate: 6/6 in" "$tmp/vp.err" && ok || bad "validate --progress"
timeout -s INT --preserve-status 2 "$RR" locus --range 20:500:100000 --limit 1e6 --progress > "$tmp/lint.csv" 2> "$tmp/lint.err"; st=$?
[ $st -eq 130 ] && grep -q "(stopped)" "$tmp/lint.err" && [ "$(wc -l < "$tmp/lint.csv")" -gt 10 ] \
  && python3 -c "import csv,sys; r=list(csv.reader(open(sys.argv[1]))); sys.exit(0 if all(len(x)==len(r[0]) for x in r) else 1)" "$tmp/lint.csv" \
  && ok || bad "locus interrupted: exit $st, $(tail -c 200 "$tmp/lint.err")"
expect2 "optimise output folder missing" "cannot write" "$RR" optimise "$SRC/examples/paper-optimisation.ini" --output /nonexistent/dir/x
# sweep over one axis and over the operating point: the values equal modes' index at each point
"$RR" sweep --x conicity=0.1:0.4:4 --objective index@350 > "$tmp/swc.csv" || bad "sweep conicity axis"
python3 - "$tmp/swc.csv" "$RR" <<'PY' && ok || bad "sweep over conicity equals modes"
import csv, json, subprocess, sys
rows = list(csv.reader(open(sys.argv[1])))
assert rows[0][:2] == ['conicity', 'index@350'] and len(rows) == 5
for r in rows[1:]:
    d = json.loads(subprocess.run([sys.argv[2], 'modes', '--speed', '350', '--conicity', r[0], '--json'], capture_output=True, text=True).stdout)
    assert abs(float(r[1]) - d['stability_index']) < 1e-9, (r, d['stability_index'])   # CSV: 10 digits
PY
"$RR" sweep --x speed=200:400:3 --y yaw_damper.series_stiffness=5MN/m:15MN/m:2 --objective "index@0,0.3" > "$tmp/sws.csv" && [ "$(wc -l < "$tmp/sws.csv")" -eq 7 ] \
  && head -1 "$tmp/sws.csv" | grep -q '^speed_kmh,yaw_damper.series_stiffness_n_per_m,' && ok || bad "sweep speed x key"

# a long map stopped by Ctrl-C: the rows done so far are written, exit 130; --progress reports an ETA
timeout -s INT --preserve-status 2 "$RR" map --speeds 100:600:5000 --conicities 0.02:0.6:200 --limit 1e7 --progress > "$tmp/bigmap.csv" 2> "$tmp/bigmap.err"; st=$?
[ $st -eq 130 ] && [ "$(wc -l < "$tmp/bigmap.csv")" -gt 100 ] && grep -q "ETA" "$tmp/bigmap.err" && grep -q "stopped" "$tmp/bigmap.err" \
  && ok || bad "map interrupted: exit $st, $(wc -l < "$tmp/bigmap.csv") rows"

# checkpoint and resume: 5 generations, then --resume to 12, equals 12 straight
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 12 --threads 1 --output "$tmp/straight" > /dev/null || bad "optimise straight"
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 5 --threads 1 --output "$tmp/rs" > /dev/null || bad "optimise first part"
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 12 --threads 1 --output "$tmp/rs" --resume > /dev/null || bad "optimise --resume"
cmp -s "$tmp/straight-pareto.csv" "$tmp/rs-pareto.csv" && [ "$(wc -l < "$tmp/rs-history.csv")" -eq 13 ] && ok || bad "resumed run = uninterrupted run"
expect2 "resume without a checkpoint" "no checkpoint" "$RR" optimise "$SRC/examples/paper-optimisation.ini" --output "$tmp/none" --resume
# SIGINT in the middle of a large generation: honoured within 2 s, that generation dropped, the last whole one written
( "$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 6000 --generations 4 --threads 2 --output "$tmp/sg" > "$tmp/sg.out" 2> "$tmp/sg.err"; echo $? > "$tmp/sg.st" ) &
sgjob=$!
for _ in $(seq 900); do sleep 0.1; [ -f "$tmp/sg-checkpoint.bin" ] && break; done
sleep 0.3
t0=$(date +%s%N)
pkill -INT -f "optimise $SRC/examples/paper-optimisation.ini --population 6000" || true
wait $sgjob
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
# (2 s; a sanitizer build runs several times slower: 8 s)
sg_limit=2000; ldd "$RR" 2> /dev/null | grep -q 'libasan\|libtsan' && sg_limit=8000
[ "$(cat "$tmp/sg.st")" = 130 ] && [ $ms -lt $sg_limit ] && grep -q "stopped by a signal after generation 1 of 4" "$tmp/sg.out" && [ -s "$tmp/sg-pareto.csv" ] \
  && ok || bad "SIGINT mid-generation: exit $(cat "$tmp/sg.st"), ${ms} ms, $(head -2 "$tmp/sg.out" | tail -1) $(cat "$tmp/sg.err")"
# a resume of a changed problem is refused, naming what changed; the previous front stays
sed 's/objective = std_zeta minimize/objective = std_zeta maximize/' "$SRC/examples/paper-optimisation.ini" > "$tmp/changed.ini"
cp "$tmp/rs-pareto.csv" "$tmp/rs-before.csv"
expect2 "resume of a changed problem" "the objectives or their sense changed" "$RR" optimise "$tmp/changed.ini" --population 40 --generations 14 --threads 1 --output "$tmp/rs" --resume
cmp -s "$tmp/rs-before.csv" "$tmp/rs-pareto.csv" && ok || bad "a refused resume left the previous front"
printf '[vehicle]\nbase = type1\n[carbody]\nmass = 40 t\n' > "$tmp/heavier.ini"
sed "s|vehicle = type1|vehicle = $tmp/heavier.ini|" "$SRC/examples/paper-optimisation.ini" > "$tmp/changedv.ini"
expect2 "resume with another vehicle" "the vehicle changed" "$RR" optimise "$tmp/changedv.ini" --population 40 --generations 14 --threads 1 --output "$tmp/rs" --resume
# nothing lost: a full disk or a failed command never leaves a damaged or emptied file
echo previous > "$tmp/keep.csv"
"$RR" ride --speed 350 --conicity 0.1 --spectrum nosuch --psd "$tmp/keep.csv" > /dev/null 2>&1
[ "$(cat "$tmp/keep.csv")" = previous ] && ok || bad "a failed ride emptied --psd"
"$RR" modes --speed 350 --conicity 0.17 > /dev/full 2> "$tmp/full.err"; st=$?
[ $st -ne 0 ] && grep -q "standard output" "$tmp/full.err" && ok || bad "stdout to a full disk: exit $st"
for args in "ride --speed 350 --conicity 0.1 --psd /dev/full" "validate --speed 300 --conicity 0.2 --duration 16 --fs 128 --nseg 256 --psd /dev/full" \
  "modes --speed 350 --conicity 0.17 --shape-data /dev/full" "map --speeds 300:400:2 --conicities 0.1:0.2:2 --json"; do
  # shellcheck disable=SC2086
  "$RR" $args > /dev/full 2> "$tmp/full.err"; st=$?
  [ $st -ne 0 ] && grep -q "No space" "$tmp/full.err" && ok || bad "$args to a full disk: exit $st"
done
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 8 --generations 1 --threads 1 --output "$tmp/full" > /dev/full 2> "$tmp/full.err"; st=$?
[ $st -ne 0 ] && grep -q "No space" "$tmp/full.err" && ok || bad "optimise's summary to a full disk: exit $st"
# the linear model fed by profiles equals the model fed by the same conicity as a number
printf -- '-70 -3.5\n0 0\n65 3.25\n' > "$tmp/cone.dat"
printf -- '-30 -30\n0 0\n30 -30\n' > "$tmp/knife.dat"
printf '[vehicle]\nbase = type1\n[contact]\nwheel = cone.dat\nrail = knife.dat\ninclination = 0\n' > "$tmp/vprof.ini"
a=$("$RR" modes "$tmp/vprof.ini" --speed 300 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["stability_index"], d["conicity"], d["conicity_source"])')
b=$("$RR" modes --speed 300 --conicity 0.05 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["stability_index"], d["conicity"], d["conicity_source"])')
c=$(cd "$tmp" && "$RR" modes --speed 300 --profiles cone.dat,knife.dat --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["stability_index"], d["conicity"])')
python3 -c 'import sys; a, b, c = (s.split() for s in sys.argv[1:4]); close = lambda x, y: all(abs(float(p) - float(q)) < 1e-9 for p, q in zip(x[:2], y[:2])); sys.exit(0 if close(a, b) and close(c, b) and " ".join(a[2:]) == "profiles cone.dat/knife.dat at 3 mm" else 1)' "$a" "$b" "$c" \
  && ok || bad "profiles as the conicity: '$a' / '$b' / '$c'"
expect2 "--profiles with --conicity" "not with --conicity" "$RR" modes --speed 300 --conicity 0.1 --profiles "$tmp/cone.dat,$tmp/knife.dat"
# the nonlinear vehicle on contact functions: a cone of slope 0.4 on a knife edge has the
# constant conicity's Hopf point (the linear critical speed), and its cycles (creep saturation
# only) appear where rest loses stability: supercritical; bifurcation takes --profiles too
printf -- '-70 -28\n0 0\n65 26\n' > "$tmp/cone4.dat"
"$RR" wear --wheels "$tmp/cone4.dat" --rail "$tmp/knife.dat" --nonlinear --json > "$tmp/wearnl.json" || bad "wear --nonlinear exit"
python3 - "$tmp/wearnl.json" <<'PY' && ok || bad "wear --nonlinear"
import json, sys
p = json.load(open(sys.argv[1]))["profiles"][0]
n = p["nonlinear"]
assert abs(n["hopf_speed_kmh"] - p["critical_speed_kmh"]) < 2e-3, (n, p["critical_speed_kmh"])
assert n["bifurcation"] == "supercritical" and abs(n["onset_kmh"] - 525) < 1e-9, n
assert n["nonlinear_critical_kmh"] <= n["onset_kmh"], n
PY
h=$(cd "$tmp" && "$RR" bifurcation --profiles cone4.dat,knife.dat --speeds 400:560 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d["linear_critical_speed_kmh"], d["profile"])')
python3 -c 'import json,sys; v, name = sys.argv[1].split(" ", 1); d = json.load(open(sys.argv[2]))["profiles"][0]; sys.exit(0 if abs(float(v) - d["nonlinear"]["hopf_speed_kmh"]) < 1e-6 and name == "profiles cone4.dat/knife.dat" else 1)' "$h" "$tmp/wearnl.json" \
  && ok || bad "bifurcation --profiles: $h"
# a wheelset that leaves the contact data ends the run: a derailment indication, exit 1
out=$(cd "$tmp" && "$RR" simulate --speed 900 --profiles cone4.dat,knife.dat --duration 10 --disturbance 5mm 2>&1 >/dev/null); rc=$?
[ $rc -eq 1 ] && echo "$out" | grep -q "beyond the contact data.*derailment indication" && ok || bad "derailment: rc $rc $out"
# examples/paper_bifurcation_study.py on a small front: its designs' files load, and a table
# row reads the Pareto CSV's columns and the bifurcation JSON's keys (the bifurcations
# themselves take minutes: one is run, design B's, on the worn tread over 100-300 km/h)
python3 - "$SRC/examples" "$RR" "$tmp" <<'PY' && ok || bad "paper_bifurcation_study.py"
import json, subprocess, sys
sys.path.insert(0, sys.argv[1])
import paper_bifurcation_study as m
rr, tmp = sys.argv[2], sys.argv[3]
d = m.choose(m.front(rr, 16, 1))
for name in "ABCD":
    path = m.write_design(name, d[name], "test", tmp)
    subprocess.run([rr, "modes", path, "--speed", "300", "--conicity", "0.1"], check=True, capture_output=True)
b = json.loads(subprocess.run([rr, "bifurcation", tmp + "/paper-design-B.ini", "--profile", "worn", "--speeds",
                               "100:300", "--json"], check=True, capture_output=True, text=True).stdout)
row = m.table_row("B", "best zeta_low", d["B"], "worn", b)
assert row.startswith("| B (best zeta_low) | ") and row.count("|") == 10, row
PY
# the wear study: EN 15302's wheels A, B, H, I on rail A give Annex E's tan gamma_e at 3 mm,
# and each profile's index is the linear model's at that conicity
P=$(cd "$SRC/profiles/en15302" && pwd)
printf '[vehicle]\nbase = type1\n[contact]\nrail = %s\ninclination = 0\ngauge_point = -32.5 mm\n' "$P/SUIC519A.dat" > "$tmp/wear.ini"
"$RR" wear "$tmp/wear.ini" --wheels "$P/RUIC519A.dat,$P/RUIC519B.dat,$P/RUIC519H.dat,$P/RUIC519I.dat" --json > "$tmp/wear.json" || bad "wear exit"
python3 - "$tmp/wear.json" "$RR" <<'PY' && ok || bad "wear study"
import json, subprocess, sys
d = json.load(open(sys.argv[1]))
ref = [0.18748, 0.03228, 0.26294, 0.49305]
for p, r in zip(d["profiles"], ref):
    assert abs(p["tan_gamma_e_3mm"] - r) < 1e-5, (p["wheel"], p["tan_gamma_e_3mm"], r)
    m = json.loads(subprocess.run([sys.argv[2], "modes", "--speed", "350", "--conicity", repr(p["tan_gamma_e_3mm"]), "--json"],
                                  capture_output=True, text=True, check=True).stdout)
    assert abs(m["stability_index"] - p["stability_index"]) < 1e-9, (p["wheel"], m["stability_index"], p["stability_index"])
assert len(d["profiles"]) == 4 and len(d["profiles"][0]["tan_gamma_e"]) == len(d["amplitude_mm"])
PY
# what wear --plot draws is what --json says (the conicity functions, then a row per profile)
"$RR" wear "$tmp/wear.ini" --wheels "$P/RUIC519A.dat,$P/RUIC519I.dat" --plot-data "$tmp/wear.dat" > /dev/null || bad "wear --plot-data exit"
python3 - "$tmp/wear.json" "$tmp/wear.dat" <<'PY' && ok || bad "wear --plot-data"
import json, math, sys
d = json.load(open(sys.argv[1]))
blocks = open(sys.argv[2]).read().split("\n\n\n")
names = [l.split(": ", 1)[1] for l in blocks[0].splitlines() if l.startswith("# profile ")]
curve = [list(map(float, l.split())) for l in blocks[0].splitlines() if l and l[0] != "#"]
rows = [list(map(float, l.split())) for l in blocks[1].splitlines() if l.strip()]
assert names == ["RUIC519A.dat", "RUIC519I.dat"], names
for j, p in enumerate((d["profiles"][0], d["profiles"][3])):
    assert [c[0] for c in curve] == d["amplitude_mm"]
    assert all(abs(c[1 + j] - t) < 1e-7 for c, t in zip(curve, p["tan_gamma_e"]))
    r = rows[j]
    assert abs(r[1] - p["tan_gamma_e_3mm"]) < 1e-7 and abs(r[2] - p["stability_index"]) < 1e-7
    cs = p["critical_speed_kmh"]
    assert (math.isnan(r[3]) and r[7] == 600) if cs is None else (abs(r[3] - cs) < 1e-5 and math.isnan(r[7])), (r, cs)
    assert all(abs(a - b) < 1e-5 for a, b in zip(r[4:7], p["sperling"]))
PY
# a file named where a vehicle, table, spectrum or problem file belongs, that is not one: no message quotes it
printf 'SECRET_TOKEN=abc123\nOTHER = [x]\n' > "$tmp/secret.env"
cp "$tmp/secret.env" "$tmp/secret.txt"
printf '[vehicle]\nbase = %s\n' "$tmp/secret.env" > "$tmp/bsec.ini"
printf '[vehicle]\nbase = type1\n[yaw_damper]\nsdf = paper\nsdf_table = %s\n' "$tmp/secret.env" > "$tmp/tsec.ini"
for args in "modes $tmp/bsec.ini --speed 300 --conicity 0.1" "modes $tmp/tsec.ini --speed 300 --conicity 0.1" \
  "ride --speed 300 --conicity 0.1 --spectrum $tmp/secret.txt" "optimise $tmp/secret.env" "bifurcation --profile $tmp/secret.env"; do
  # shellcheck disable=SC2086
  "$RR" $args > /dev/null 2> "$tmp/sec.err"; st=$?
  [ $st -eq 2 ] && ! grep -q "SECRET\|abc123\|OTHER" "$tmp/sec.err" && ok || bad "$args: exit $st, quotes the file: $(cat "$tmp/sec.err")"
done
# a file-size limit (as a full disk): optimise fails with a message, the previous front intact
echo previous > "$tmp/fz-pareto.csv"
( trap '' XFSZ; ulimit -f 1; "$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 2 --threads 1 --output "$tmp/fz" > /dev/null 2> "$tmp/fz.err" ); st=$?
[ $st -ne 0 ] && grep -q "File too large" "$tmp/fz.err" && [ "$(cat "$tmp/fz-pareto.csv")" = previous ] && ok || bad "optimise at a file-size limit: exit $st $(cat "$tmp/fz.err")"
# a 150 MB comment line under a 200 MB memory cap: read past, the keys after it still read
{ printf '[vehicle]\nbase = type1\n#'; head -c 150000000 /dev/zero | tr '\0' x; printf '\n[carbody]\nmass = 1 g\n'; } > "$tmp/long.ini"
if [ -z "${ASAN_OPTIONS:-}" ]; then  # AddressSanitizer's shadow memory does not fit under the cap
  ( ulimit -v 200000; "$RR" modes "$tmp/long.ini" --speed 300 --conicity 0.1 > /dev/null 2> "$tmp/long.err" ); st=$?
  [ $st -eq 2 ] && grep -q "long.ini:5: \[carbody\] mass" "$tmp/long.err" && ok || bad "a long line under a memory cap: exit $st $(cat "$tmp/long.err")"
fi
rm -f "$tmp/long.ini"
# no user string reaches a shell or gnuplot as code; --plot leaves nothing beside the user's files
mkdir "$tmp/inj"
( cd "$tmp/inj" && "$RR" ride --speed 350 --conicity 0.1 --psd 'p$(touch inj1).csv' --plot 'q`touch inj2`.png' > /dev/null 2>&1 \
  && "$RR" sweep --x conicity=0.1:0.2:2 --objective 'index@350;fmax=10' --plot 'r$(touch inj3)`touch inj4`.svg' > /dev/null 2>&1 )
[ ! -e "$tmp/inj/inj1" ] && [ ! -e "$tmp/inj/inj2" ] && [ ! -e "$tmp/inj/inj3" ] && [ ! -e "$tmp/inj/inj4" ] \
  && [ -s "$tmp/inj/q\`touch inj2\`.png" ] && ok || bad "a file name ran a command"
[ "$(ls -A "$tmp/inj" | wc -l)" -eq 3 ] && ok || bad "--plot left files beside the user's: $(ls -A "$tmp/inj")"

# constraints: every design on the constrained front is feasible (stable at both points); the front is also JSON, each design once
"$RR" optimise "$SRC/examples/paper-optimisation-constrained.ini" --population 60 --generations 8 --threads 2 --output "$tmp/pc" > /dev/null || bad "constrained optimise exit"
python3 - "$tmp/pc-pareto.csv" "$tmp/pc-pareto.json" <<'PY' && ok || bad "constrained front"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert rows and all(r['feasible'] == '1' and float(r['violation']) == 0 for r in rows)
assert all(float(r['zeta_low']) <= 0 and float(r['zeta_high']) <= 0 for r in rows)
keys = [tuple(r[k] for k in list(r)[:4]) for r in rows]
assert len(keys) == len(set(keys)), 'duplicates on the front'
d = json.load(open(sys.argv[2]))
assert len(d['front']) == len(rows) and all(f['feasible'] for f in d['front'])
PY

# the vertical model: ride (keys as docs/vertical.md), its PSD file, both directions' EN 12299, modes, frf
"$RR" ride --speed 350 --direction vertical --json --psd "$tmp/vpsd.csv" > "$tmp/v.json" || bad "ride vertical exit"
json_check "ride vertical keys" "d['direction']=='vertical' and d['spectrum']=='tbt3352-vertical' and d['window_s']==5 and len(d['points'])==3 and all(set(p)>={'x','rms','sperling','sperling_gb','wk_rms','wb_rms','wb_iso8041_rms','wb_5s','n_mv_vertical','lateral','n_mv','n_vd','n_va_rigid_seat'} and set(p['wb_5s'])>={'shape_k','dof','p50','p95','mean'} and p['n_mv'] is None and abs(p['n_mv_vertical']-6*p['wb_5s']['p95'])<1e-12 for p in d['points'])" < "$tmp/v.json"
json_check "ride vertical: the rear point's P95 (docs/vertical.md table)" "abs(d['points'][2]['wb_5s']['p95']-0.04607)<5e-6 and abs(d['points'][0]['x']-8.6875)<1e-12" < "$tmp/v.json"
python3 - "$tmp/vpsd.csv" "$tmp/v.json" <<'PY' && ok || bad "vertical psd csv integrates to rms and wb_rms"
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
pts = json.load(open(sys.argv[2]))['points']
f = [float(r['f_hz']) for r in rows]
for p in pts:
    col = 'psd_x%gm_m2s-4_per_hz' % p['x']
    g = [float(r[col]) for r in rows]
    wb = [float(r['wb_en12299_weight2']) * x for r, x in zip(rows, g)]
    tz = lambda y: sum(0.5 * (y[i] + y[i + 1]) * (f[i + 1] - f[i]) for i in range(len(f) - 1))
    assert abs(math.sqrt(tz(g)) / p['rms'] - 1) < 1e-8 and abs(math.sqrt(tz(wb)) / p['wb_rms'] - 1) < 1e-8
PY
"$RR" ride --speed 350 --conicity 0.17 --direction both --json > "$tmp/vb.json" || bad "ride both exit"
json_check "ride both: N_MV from the two directions' P95" "all(abs(p['n_mv']-6*math.hypot(p['lateral']['wd_p95'],p['wb_5s']['p95']))<1e-12 and p['comfort']=='very comfortable' and p['n_vd']>0 and p['n_va_rigid_seat']>0 for p in d['points']) and d['conicity']==0.17" < "$tmp/vb.json"
"$RR" ride --speed 350 --conicity 0.17 --direction both | grep -q "very comfortable" && ok || bad "ride both: the comfort scale in text"
"$RR" modes --direction vertical --json > "$tmp/vm.json" || bad "modes vertical exit"
json_check "modes vertical" "len(d['modes'])==7 and len(d['undamped_hz'])==7 and abs(d['phi_unit_centre']-1.2156444588)<1e-9 and all(abs(sum(m['energy'].values())-1)<1e-12 and 0<m['damping_ratio']<1 for m in d['modes']) and len({m['name'] for m in d['modes']})==7 and d['modes'][-1]['name']=='carbody first bending'" < "$tmp/vm.json"
"$RR" frf --speed 350 --direction vertical --dofs --json > "$tmp/vf.json" || bad "frf vertical exit"
json_check "frf vertical" "len(d['f_hz'])==400 and len(d['points'])==3 and all(abs(a-math.hypot(r,i))<=1e-12*max(a,1) for p in d['points'] for r,i,a in zip(p['re'],p['im'],p['abs'])) and set(d['dofs'])=={'z_c','theta_c','q_b','z_f1','theta_f1','z_f2','theta_f2'}" < "$tmp/vf.json"
"$RR" sweep --x speed=250:350:2 --objective "n_mv@350,0.17,-8.6875" > "$tmp/nmv.csv" || bad "sweep n_mv exit"
python3 - "$tmp/nmv.csv" "$tmp/vb.json" <<'PY' && ok || bad "sweep n_mv at 350 km/h = ride both's"
import csv, json, sys
rows = list(csv.reader(open(sys.argv[1])))
assert abs(float(rows[2][1]) - json.load(open(sys.argv[2]))['points'][2]['n_mv']) < 1e-9
PY
"$RR" validate --speed 350 --direction vertical --json --psd "$tmp/vval.csv" > "$tmp/vval.json" || bad "validate vertical exit"
json_check "validate vertical" "d['verdict']=='PASS' and d['track_amplitudes']=='gaussian' and len(d['points'])==3 and all(p['frf_line_error_max']<1e-3 and abs(p['rms_z'])<4 and len(p['bands'])==17 and p['windows']==120 for p in d['points'])" < "$tmp/vval.json"
head -1 "$tmp/vval.csv" | grep -q "^f_hz,welch_x8.6875m_m2s-4_per_hz" && ok || bad "validate vertical --psd header"
"$RR" validate --speed 350 --conicity 0.2 --json > "$tmp/lval.json" || bad "validate lateral exit"
json_check "validate lateral: Gaussian track, z-scores" "d['track_amplitudes']=='gaussian' and d['verdict']=='PASS' and all(abs(p['rms_z'])<4 and abs(p['sperling_z'])<4 and p['rms_rel_std']>0 for p in d['points'])" < "$tmp/lval.json"
expect2 "validate vertical needs speed" "--speed is required" "$RR" validate --direction vertical
expect2 "validate vertical takes no conicity" "conicity" "$RR" validate --speed 350 --direction vertical --conicity 0.2
expect2 "validate amplitudes" "--track-amplitudes: gaussian or fixed" "$RR" validate --speed 350 --conicity 0.2 --track-amplitudes big
"$RR" ride --speed 350 --direction both --conicity 0.17 --ax-pitch --json > "$tmp/vax.json" || bad "ride --ax-pitch exit"
json_check "ax-pitch: pitch's longitudinal Wd RMS (docs/vertical.md: 0.74e-3 m/s2)" "abs(d['points'][0]['longitudinal']['wd_rms']-0.742e-3)<5e-6 and d['ax_pitch'] is True and d['hp']==1.2 and all(p['longitudinal']['wc_p95']>0 for p in d['points'])" < "$tmp/vax.json"
"$RR" ride --speed 350 --direction vertical --lateral-wd-p95 0.08,0.02,0.09 --json > "$tmp/vlat.json" || bad "ride --lateral-wd-p95 exit"
json_check "lateral-wd-p95: N_MV from the given lateral P95" "all(abs(p['n_mv']-6*math.hypot(a,p['wb_5s']['p95']))<1e-12 and p['lateral']['wd_rms'] is None for p,a in zip(d['points'],(0.08,0.02,0.09)))" < "$tmp/vlat.json"
expect2 "ax-pitch with given ax" "--ax-pitch: not with" "$RR" ride --speed 350 --direction vertical --ax-pitch --ax-p95 0.01
expect2 "lateral given with both" "--lateral-wd-p95: with --direction vertical" "$RR" ride --speed 350 --conicity 0.2 --direction both --lateral-wd-p95 0.1
expect2 "lateral given: count" "one value or one per floor point" "$RR" ride --speed 350 --direction vertical --lateral-wd-rms 0.1,0.2
"$RR" matrices --direction vertical --speed 350 --json > "$tmp/vmat.json" || bad "matrices vertical exit"
json_check "matrices vertical" "len(d['K'])==7 and len(d['BK'][0])==4 and len(d['A'])==14 and abs(d['K'][2][2]-3955.287)<1e-3 and abs(d['delays_s'][3]-(2*8.6875+2.5)/(350/3.6))<1e-15 and d['dofs'][2]=='q_b'" < "$tmp/vmat.json"
printf '{"name": "car-b", "base": "type1", "carbody": {"mass": 40000, "length": "26 m"}}\n' > "$tmp/carb.json"
"$RR" modes "$tmp/carb.json" --direction vertical --json | python3 -c "import json,sys; d=json.load(sys.stdin); sys.exit(0 if d['vehicle']=='car-b' and len(d['modes'])==7 else 1)" && ok || bad "a JSON vehicle file"
printf '{\n "carbody": {\n  "mass": "4 kg"}}\n' > "$tmp/badj.json"
expect2 "JSON vehicle: the key's line" "badj.json:3: \[carbody\] mass" "$RR" ride "$tmp/badj.json" --speed 350 --direction vertical
expect2 "direction unknown" "--direction: lateral, vertical or both" "$RR" ride --speed 350 --direction sideways
expect2 "vertical takes no --spectrum" "--vertical-spectrum" "$RR" ride --speed 350 --direction vertical --spectrum wuhan-guangzhou
expect2 "lateral takes no --window" "--window: only with --direction" "$RR" ride --speed 350 --conicity 0.1 --window 5
expect2 "both takes one conicity" "one value with --direction both" "$RR" ride --speed 350 --conicity 0.1,0.2 --direction both
expect2 "vertical input must be vertical" "a lateral spectrum, not vertical" "$RR" ride --speed 350 --direction vertical --vertical-spectrum wuhan-guangzhou
expect2 "vertical takes no --conicity" "conicity" "$RR" ride --speed 350 --direction vertical --conicity 0.2
printf '[vehicle]\nbase = type1\n[carbody]\nlength = 17 m\n' > "$tmp/short.ini"
expect2 "pivots off the carbody" "\[carbody\] length" "$RR" ride "$tmp/short.ini" --speed 350 --direction vertical
printf '[vehicle]\nbase = type1\n[carbody]\nbending_frequency = 500 Hz\n' > "$tmp/bf.ini"
expect2 "bending frequency range" "bf.ini.*bending_frequency" "$RR" modes "$tmp/bf.ini" --direction vertical
expect2 "modes both" "--direction lateral or vertical" "$RR" modes --direction both

# docs/cli.md is the commands' --help, regenerated; bash completion offers commands and a command's options
sh "$SRC/tools/gen-cli-docs" "$(dirname "$RR")" | diff -q - "$SRC/docs/cli.md" > /dev/null && ok || bad "docs/cli.md is stale: tools/gen-cli-docs build > docs/cli.md"
comp() { RR="$RR" bash -c 'source "$1"; shift; PATH="$(dirname "$RR"):$PATH"; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _railride; echo "${COMPREPLY[*]}"' _ "$SRC/share/railride-completion.bash" "$@"; }
comp railride bif | grep -qw bifurcation && ok || bad "completion: commands"
comp railride bifurcation --pro | grep -qw -- --profile && ok || bad "completion: a command's options"
echo "cli: $pass passed, $fail failed"
[ $fail -eq 0 ]

#!/usr/bin/env bash
# --plot: every command that draws renders a PNG that is not blank, an SVG
# and a PDF by extension, and a missing gnuplot or a bad extension is a
# one-line error with status 2.
set -u
RR=${RR_CLI:?RR_CLI must name the railride binary}
SRC=${RR_SOURCE_DIR:-..}
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
png() {  # png NAME ARGS...: railride ARGS --plot NAME.png, then the picture checked
  local name=$1; shift
  if "$RR" "$@" --plot "$tmp/$name.png" > "$tmp/$name.out" 2> "$tmp/$name.err"; then
    python3 "$SRC/tests/png_check.py" "$tmp/$name.png" > /dev/null && ok || bad "$name: blank picture"
    grep -q "gnuplot" "$tmp/$name.err" && bad "$name: gnuplot warned: $(grep gnuplot "$tmp/$name.err" | head -1)" || ok
  else
    bad "$name: exit $? ($(head -2 "$tmp/$name.err"))"
  fi
}
png damper damper
png modes modes --speed 350 --conicity 0.17
png contact contact --wheel "$SRC/profiles/en15302/RUIC519H.dat" --rail "$SRC/profiles/en15302/SUIC519A.dat" --rail-gmp -32.5
P=$(cd "$SRC/profiles/en15302" && pwd)
printf '[vehicle]\nbase = type1\n[contact]\nrail = %s\ninclination = 0\ngauge_point = -32.5 mm\n' "$P/SUIC519A.dat" > "$tmp/wear.ini"
png wear wear "$tmp/wear.ini" --wheels "$P/RUIC519A.dat,$P/RUIC519I.dat"
png locus locus --over conicity --range 0.05:0.6:12 --speed 300
png map map --speeds 200:500:4 --conicities 0.05:0.5:4
png sweep sweep --x "primary.longitudinal_stiffness=10 kN/mm:120 kN/mm:4" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:4" --objective "index@350,0.17"
png ride ride --speed 300 --conicity 0.1,0.4
png ride_vertical ride --speed 350 --direction both --conicity 0.17
png compare compare --conicities 0.05:0.5:3
png validate validate --speed 300 --conicity 0.2 --duration 16 --fs 128 --nseg 256
png bifurcation bifurcation --profile worn --speeds 100:560
png optimise optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 5 --output "$tmp/po"
png scan bifurcation --profile worn --method scan --speeds 530:560 --step 15 --settle 4
png sweepkc sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:5" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:5" --objective "index@350,0.17"
# the columns a script plots, read back against the data's header: a wrong column cannot come back
cols_check() {  # cols_check WHAT PATTERN NAME ARGS...: the script's $N matched by PATTERN is column NAME
  local what=$1 pat=$2 name=$3; shift 3
  mkdir -p "$tmp/cc" && rm -f "$tmp/cc"/*
  (cd "$tmp/cc" && "$RR" "$@" --plot p.svg --plot-script p.gp > out.csv 2> /dev/null) || { bad "$what: exit"; return; }
  python3 - "$tmp/cc/p.gp" "$tmp/cc/out.csv" "$pat" "$name" <<'PY' && ok || bad "$what"
import re, sys
gp, csv, pat, name = sys.argv[1:]
cols = re.findall(pat, open(gp).read())
head = open(csv).readline().strip().split(",")
assert cols and all(head[int(c) - 1] == name for c in cols), (cols, head, name)
PY
}
cols_check "sweep: the range-end points from at_range_end" '\(\$(\d+) > 0 \? \$2' at_range_end \
  sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:5" --objective "critical_speed@0.17"
cols_check "sweep 2-D: the range-end points from at_range_end" '\(\$(\d+) > 0 \? \$3' at_range_end \
  sweep --x "primary.longitudinal_stiffness=10 kN/mm:120 kN/mm:3" --y "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:3" --objective "critical_speed@0.17"
cols_check "map --shares: the carbody panel draws hunting_e_carbody" 'u \(\$1/sx\):\(\$2/sy\):(10) w pm3d' hunting_e_carbody \
  map --speeds 200:600:3 --conicities 0.05:0.5:3 --shares
cols_check "map --shares: the frames panel draws hunting_e_frames" 'u \(\$1/sx\):\(\$2/sy\):(11) w pm3d' hunting_e_frames \
  map --speeds 200:600:3 --conicities 0.05:0.5:3 --shares
# compare at unstable conicities: the undefined ride is an empty cell the picture leaves out
"$RR" compare --speed 450 --conicities 0.2:0.6:3 --csv 2> /dev/null | awk -F, 'NR > 1 && $5 == "" {n++} END {exit !(n >= 2)}' && ok ||
  bad "compare: an unstable point's Sperling is an empty cell"
# what each picture must show besides its curves (gnuplot's SVG keeps legend texts)
svg_has() {  # svg_has WHAT TEXT ARGS...: railride ARGS --plot F.svg shows TEXT
  local what=$1 text=$2; shift 2
  "$RR" "$@" --plot "$tmp/t.svg" > /dev/null 2>&1 && grep -q "$text" "$tmp/t.svg" && ok || bad "$what: no '$text' in the picture"
}
svg_has "sweep: the k = c w line" "k = c w" sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:5" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:5" --objective "index@350,0.17"
svg_has "sweep: axis units" "yaw damper damping (kN s/m)" sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:3" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:3" --objective "index@350,0.17"
svg_has "modes: a panel per mode, the index's marked" "sets the index" modes --speed 350 --conicity 0.17
svg_has "modes: roll marked" "roll " modes --speed 250 --conicity 0.05
svg_has "contact: the conicity panel" "equivalent conicity" contact --wheel "$SRC/profiles/en15302/RUIC519A.dat" --rail "$SRC/profiles/en15302/SUIC519A.dat" --rail-gmp -32.5
svg_has "wear: a panel per result, the profiles named" "RUIC519I.dat" wear "$tmp/wear.ini" --wheels "$P/RUIC519A.dat,$P/RUIC519I.dat"
svg_has "wear: the critical speed panel" "linear critical speed" wear "$tmp/wear.ini" --wheels "$P/RUIC519A.dat,$P/RUIC519I.dat"
svg_has "ride: the Sperling weighting" "Sperling weighting (right)" ride --speed 300 --conicity 0.2
svg_has "ride vertical: the Wb weighting" "EN 12299 Wb (right)" ride --speed 300 --direction vertical
svg_has "compare: the N_MV panel" "EN 12299 N_MV" compare --conicities 0.05:0.4:2
svg_has "validate: the spread band" "2 sigma of a Welch bin" validate --speed 300 --conicity 0.2 --duration 16 --fs 128 --nseg 256
svg_has "map: the zero contour" "index = 0" map --speeds 200:600:4 --conicities 0.05:0.5:4
svg_has "ride: legends that say what a curve is" "conicity 0.1, floor x = 8.6875 m" ride --speed 300 --conicity 0.1,0.4
svg_has "ride both: vertical and lateral named" "vertical, floor x = 0 m" ride --speed 350 --direction both --conicity 0.17
svg_has "ride: what the picture is of" "type1, 300 km/h, conicity 0.1,0.4" ride --speed 300 --conicity 0.1,0.4
svg_has "damper: the vehicle file named" "type1-sdf-paper.ini" damper "$SRC/examples/type1-sdf-paper.ini"
svg_has "map: the vehicle file named (getopt reorders the arguments)" "paper-design-A.ini" map "$SRC/examples/paper-design-A.ini" --speeds 200:300:2 --conicities 0.1:0.2:2
svg_has "map: the vehicle file named after the options" "paper-design-B.ini" map --speeds 200:300:2 --conicities 0.1:0.2:2 "$SRC/examples/paper-design-B.ini"
svg_has "bifurcation: the Hopf point" "Hopf 5[0-9.]* km/h" bifurcation --profile worn --speeds 100:600
svg_has "bifurcation: the straight-running branch" "straight running, unstable" bifurcation --profile worn --speeds 100:600
# locus: the least damped branch named at its least damped point, the label's zeta the CSV's
loc="locus --over speed --range 100:500:9 --conicity 0.17"
top=$("$RR" $loc | awk -F, 'NR > 1 && (m == "" || $7 > m) {m = $7; b = $9 > $10 && $9 > $11 ? "carbody" : $10 > $11 ? "bogie frames" : "wheelsets"} END {printf "%s[a-z ()]*, zeta %.3f", b, m}')
svg_has "locus: the least damped mode named ($top)" "$top" $loc
svg_has "map --shares: the bogie panel" "bogie frames" map --speeds 200:600:4 --conicities 0.05:0.5:4 --shares
svg_has "damper: the series stiffness, in MN/m" "series stiffness k_s(f)" damper "$SRC/examples/type1-sdf-paper.ini"
svg_has "damper: a curve per series stiffness" "k_s = 20 MN/m" damper --k "5 MN/m,10 MN/m,20 MN/m"
svg_has "sweep: the paper's -0.3 contour" "index = -0.3" sweep --x "primary.longitudinal_stiffness=10 kN/mm:120 kN/mm:6" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:6" --objective "index@350,0.17"
"$RR" map --speeds 200:300:3 --conicities 0.1:0.2:3 --plot "$tmp/t.svg" > /dev/null 2>&1 && ! grep -q "index = 0" "$tmp/t.svg" && ok || bad "map: no zero-contour key where the index does not cross 0"
"$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 3 --output "$tmp/pp" > /dev/null 2>&1
# optimise's three-objective front: the letters A-D at railride pareto's cluster centres
mkdir -p "$tmp/f3" && (cd "$tmp/f3" && "$RR" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 3 --output f3 --plot f3.svg --plot-script f3.gp > /dev/null 2>&1) &&
  "$RR" pareto "$tmp/f3/f3-pareto.csv" --json > "$tmp/f3/cl.json" &&
  python3 - "$tmp/f3/f3.gp" "$tmp/f3/cl.json" <<'PY' && ok || bad "optimise: the clusters' letters at pareto's centres"
import json, re, sys
marks = re.findall(r"set label 20\d '([A-D])' at ([^,]+), ([^ ]+) ", open(sys.argv[1]).read())
cl = {c["name"]: c["centre"] for c in json.load(open(sys.argv[2]))["clusters"]}
assert len(marks) == 4 == len(cl), marks
for name, x, y in marks:
    assert abs(float(x) - cl[name]["zeta_low"]) < 1e-12 and abs(float(y) - cl[name]["zeta_high"]) < 1e-12, (name, x, y, cl[name])
PY
svg_has "pareto: the clusters named" "cluster D" pareto "$tmp/pp-pareto.csv"
svg_has "pareto: the yaw damper's variables in engineering units" "yaw damper damping (kN s/m)" pareto "$tmp/pp-pareto.csv"
printf '[vehicle]\nbase = type2\nname = CRH380A\n' > "$tmp/crh.ini"
svg_has "compare: a vehicle file's own name on its curves" "CRH380A SDF" compare "$tmp/crh.ini" --conicities 0.05:0.4:3
svg_has "damper: engineering units" "stiffness (MN/m)" damper
svg_has "optimise: three objectives, the third as colour" "std_zeta" optimise "$SRC/examples/paper-optimisation.ini" --population 40 --generations 3 --output "$tmp/po3"
# a constrained problem's picture shows its objectives only
"$RR" optimise "$SRC/examples/paper-optimisation-constrained.ini" --population 40 --generations 3 --output "$tmp/poc" --plot "$tmp/poc.svg" > /dev/null 2>&1 &&
  grep -q "zeta_high" "$tmp/poc.svg" && ! grep -q "feasible\|violation" "$tmp/poc.svg" && ok || bad "optimise: constrained Pareto plot draws feasible or violation"
# the data still reaches standard output where the command prints CSV
head -1 "$tmp/map.out" | grep -q '^speed_kmh,conicity,stability_index' && ok || bad "map --plot: the CSV still printed"
"$RR" compare --conicities 0.1:0.2:2 --csv --plot "$tmp/cc.png" | head -1 | grep -q '^vehicle,conicity,stability_index_const' && ok || bad "compare --csv --plot: the CSV still printed"
# --plot leaves standard output as it is without it (the wall time of a run aside)
# (every command that draws)
for args in "compare --conicities 0.05:0.5:3" "bifurcation --profile worn --speeds 100:560" \
            "bifurcation --profile worn --method scan --speeds 530:560 --step 15 --settle 4" \
            "damper" "damper --k 5e6,1e7" "modes --speed 350 --conicity 0.17" \
            "locus --over conicity --range 0.05:0.6:5 --speed 300" "map --speeds 200:500:3 --conicities 0.05:0.5:3" \
            "sweep --x yaw_damper.damping=1e5:4e6:3 --y yaw_damper.series_stiffness=1e6:3e7:3 --objective index@350,0.17" \
            "ride --speed 300 --conicity 0.2" "validate --speed 300 --conicity 0.2 --duration 16 --fs 128 --nseg 256" \
            "wear $tmp/wear.ini --wheels $P/RUIC519A.dat,$P/RUIC519I.dat" \
            "contact --wheel $P/RUIC519A.dat --rail $P/SUIC519A.dat --rail-gmp -32.5" \
            "pareto $tmp/pp-pareto.csv" "optimise $SRC/examples/paper-optimisation.ini --population 8 --generations 1 --output $tmp/same"; do
  "$RR" $args 2>/dev/null | sed 's/([0-9.]* s)//; s/, [0-9.]* s)/)/; s/ in [0-9.]* s.*$/ in T s/' > "$tmp/plain.out"
  "$RR" $args --plot "$tmp/same.png" 2>/dev/null | sed 's/([0-9.]* s)//; s/, [0-9.]* s)/)/; s/ in [0-9.]* s.*$/ in T s/' > "$tmp/plot.out"
  cmp -s "$tmp/plain.out" "$tmp/plot.out" && [ -s "$tmp/plain.out" ] && ok || bad "$args --plot changes standard output"
done
# every command that draws lists --plot in its --help, and no other does
for c in damper modes locus map sweep ride validate compare bifurcation optimise wear contact pareto; do
  "$RR" $c --help | grep -q '^  --plot FILE' && ok || bad "$c --help: no --plot"
done
"$RR" keys --help | grep -q -- '--plot' && bad "keys --help lists --plot" || ok
# --plot-script: the script and its data, which redraw the same picture in their folder
mkdir -p "$tmp/ps"
(cd "$tmp/ps" && "$RR" map --speeds 100:500:5 --conicities 0.05:0.4:4 --plot m.png --plot-script m.gp > /dev/null &&
  mv m.png first.png && gnuplot m.gp && cmp -s m.png first.png && grep -q "^speed_kmh,conicity" m.csv) && ok || bad "--plot-script: the script does not redraw the picture"
(cd "$tmp/ps" && "$RR" damper --plot "d\`touch pwned\`.png" --plot-script d.gp > /dev/null 2>&1; [ $? -eq 2 ] && [ ! -e pwned ] && ! ls d* > /dev/null 2>&1) && ok || bad "--plot-script: a name that is not plain is refused"
# SVG and PDF by extension
"$RR" damper --plot "$tmp/d.svg" > /dev/null && grep -q '<svg' "$tmp/d.svg" && ok || bad "svg"
"$RR" damper --plot "$tmp/d.pdf" > /dev/null && head -c 5 "$tmp/d.pdf" | grep -q '%PDF' && ok || bad "pdf"
# errors
expect2() {
  local name=$1 pat=$2; shift 2
  "$@" > /dev/null 2> "$tmp/err"; local st=$?
  [ $st -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q -- "$pat" "$tmp/err" && ok || bad "$name: exit $st, '$(cat "$tmp/err")'"
}
expect2 "bad extension" "must end in .svg, .png or .pdf" "$RR" damper --plot "$tmp/d.gif"
expect2 "--plot-script alone" "goes with --plot" "$RR" damper --plot-script "$tmp/d.gp"
expect2 "--plot-script extension" "must end in .gp" "$RR" damper --plot "$tmp/d.png" --plot-script "$tmp/d.txt"
expect2 "no gnuplot" "gnuplot-nox" env PATH=/nonexistent "$RR" damper --plot "$tmp/d.png"
expect2 "not a drawing command" "not an option of this command" "$RR" robust --plot "$tmp/m.png"
expect2 "unwritable" "cannot write" "$RR" damper --plot /nonexistent/dir/d.png
echo "plots: $pass passed, $fail failed"
[ $fail -eq 0 ]

#!/bin/sh
# The paper's figures from the built-in vehicles, one command:
#   examples/paper-figures.sh OUTDIR
# writes OUTDIR/figN.svg, the data of each (figN.csv) and OUTDIR/index.html,
# which shows each beside what the paper's figure shows and the command that
# made it. RAILRIDE names the binary (default: build/railride of this tree).
set -eu
OUT=${1:?usage: examples/paper-figures.sh OUTDIR}
HERE=$(cd "$(dirname "$0")/.." && pwd)
RR=${RAILRIDE:-$HERE/build/railride}
mkdir -p "$OUT"
cd "$OUT"
FIGS=""

fig() {   # fig ID "PAPER" "RAILRIDE" "DIFFERS" ARGS...: railride ARGS --plot ID.svg, data in ID.csv
  id=$1; paper=$2; ours=$3; differs=$4; shift 4
  "$RR" "$@" --plot "$id.svg" > "$id.csv"
  [ ! -f "$id-pareto.csv" ] || { mv "$id-pareto.csv" "$id.csv"; rm -f "$id-checkpoint.bin"; }  # optimise: the front is the data
  [ -s "$id.csv" ] && [ -s "$id.svg" ] || { echo "paper-figures: $id: no data or no picture" >&2; exit 1; }
  # the command as a user would type it: paths inside this tree shown relative to it
  # (and an argument with a space quoted)
  cmd=railride
  for a in "$@"; do case $a in *" "*) cmd="$cmd '$a'" ;; *) cmd="$cmd $a" ;; esac; done
  cmd=$(printf '%s' "$cmd" | awk -v here="$HERE/" '{ while ((i = index($0, here)) > 0) $0 = substr($0, 1, i - 1) substr($0, i + length(here)); print }')
  FIGS="$FIGS
<figure id=\"$id\"><img src=\"$id.svg\" alt=\"$id\"><figcaption><b>$id.</b>
<b>Paper:</b> $paper <b>railride:</b> $ours <b>Differs:</b> $differs
<a href=\"$id.csv\">data (CSV)</a><br><code>$(printf '%s' "$cmd" | sed 's/&/\&amp;/g; s/</\&lt;/g')</code></figcaption></figure>"
}

fig fig2 "Fig. 2, the yaw damper as a Maxwell element: its characteristics over frequency for several series stiffnesses." \
  "Type 1's yaw damper (c = 4000 kN s/m) with series stiffnesses 2.5, 5, 10 and 20 MN/m: equivalent (storage) stiffness and equivalent damping (loss / omega) from 0.1 to 30 Hz." \
  "the series stiffnesses are chosen around Type 1's 10 MN/m; the loss stiffness and the dissipation factor are in the CSV (one series stiffness: railride damper draws them)." \
  damper --k "2.5 MN/m,5 MN/m,10 MN/m,20 MN/m"
fig fig3 "Fig. 3, the Pareto front of the NSGA-II optimisation: zeta_low against zeta_high, coloured by std_zeta, clusters A-D marked." \
  "the same front from examples/paper-optimisation.ini with 200 designs over 30 generations (the paper: 5000 over 100), coloured by std_zeta; the letters A-D sit at the centres of the clusters of railride pareto (fig4)." \
  "a smaller run, so a sparser front; the clusters come from k-means and are named by the designs they hold, as examples/paper-design-A.ini to D.ini are chosen (A the best zeta_high, B the best zeta_low, C the best std_zeta stable at both robust points, D the nearest the ideal point)." \
  optimise "$HERE/examples/paper-optimisation.ini" --population 200 --generations 30 --output fig3
fig fig4 "Figs. 3, 4 and 6: the front's clusters A-D, the distribution of each cluster's suspension parameters, and the optimal yaw damping and series stiffness." \
  "fig3's front in four clusters by k-means over the three objectives (each scaled to [0, 1]): the front coloured by cluster (zeta_low against zeta_high, and zeta_high against std_zeta), each parameter over its range on the front per cluster, and the designs' yaw damping against series stiffness." \
  "the paper's clustering method is not stated in our sources; k-means from a farthest-point start is deterministic; the clusters are named by the designs they hold, by the rules that chose examples/paper-design-A.ini to D.ini (when the four fall in four clusters)." \
  pareto fig3.csv --csv
fig fig5 "Fig. 5a, the stability index over the primary longitudinal stiffness and the yaw damper's series stiffness." \
  "the same map for Type 1 at 350 km/h, conicity 0.17; the solid black line is index 0, the dashed one index -0.3." \
  "none in kind: the dashed line is the paper's -0.3 contour (where it lies inside the grid)." \
  sweep --x "primary.longitudinal_stiffness=10 kN/mm:120 kN/mm:23" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:30" --objective "index@350,0.17"
for c in A B C D; do
  fig "fig7$(printf %s "$c" | tr A-D a-d)" "Fig. 7, the stability index over speed and conicity for the designs of clusters A-D." \
    "cluster $c's design (examples/paper-design-$c.ini): blue stable, red unstable, black the zero line." \
    "the designs are railride's picks from its own front (the paper gives cluster regions, not single designs)." \
    map "$HERE/examples/paper-design-$c.ini" --speeds 100:500:41 --conicities 0.02:0.5:25
done
fig fig8a "Fig. 8a, root loci over speed at conicity 0.1." \
  "every oscillatory mode of Type 1 from 100 to 500 km/h at conicity 0.1, coloured by speed." \
  "none in the settings; the paper labels the modes; here the CSV gives each branch's energy shares (e_carbody, e_frames, e_wheelsets)." \
  locus --over speed --range 100:500:81 --conicity 0.1
fig fig8b "Fig. 8b, root loci over conicity at 350 km/h." \
  "every oscillatory mode of Type 1 over conicity 0.02-0.5 at 350 km/h, coloured by conicity." \
  "as Fig. 8a." \
  locus --over conicity --range 0.02:0.5:49 --speed 350
fig fig9a "Fig. 9, hunting limit cycles of the new and worn treads against speed, with the Hopf points and folds." \
  "Type 1 on the worn tread: the branch of limit cycles born at the Hopf point, continued in speed (filled stable, hollow unstable)." \
  "the paper's tread functions are not published: railride's worn tread is an assumed lambda(a)." \
  bifurcation --profile worn --speeds 100:600
fig fig9b "Fig. 9 (its subcritical case): unstable cycles from the Hopf point down to a fold, the nonlinear critical speed." \
  "a tread whose conicity rises with displacement (examples/type1-rising-tread.ini): a subcritical bifurcation." \
  "an illustrative tread, not the paper's." \
  bifurcation "$HERE/examples/type1-rising-tread.ini" --speeds 100:620
fig fig10 "Fig. 10, the stability index over the yaw damper's damping c_sx and series stiffness k_ncsx, with the line k = c omega." \
  "the same axes for Type 1 at 350 km/h, conicity 0.17, with k = c omega of the mode that sets the index (dashed green) and the zero line." \
  "none in the layout; the index values follow railride's Type 1." \
  sweep --x "yaw_damper.damping=100 kN.s/m:4000 kN.s/m:40" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:30" --objective "index@350,0.17"
fig fig10b "Fig. 10's point made over conicity: where the best series stiffness lies as the conicity changes." \
  "the index over conicity and series stiffness at 350 km/h: the best stiffness rises with conicity." \
  "not a figure of the paper: railride's own view of how the best stiffness moves with conicity." \
  sweep --x conicity=0.05:0.4:8 --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:30" --objective index@350
fig fig11a "Fig. 11, the frequency-dependent series stiffness (SDF) of the two designs' yaw dampers." \
  "Type 1's Table 2 curve k_s(f) (dotted) and the damper's storage and loss stiffness with it." \
  "none in the curve; the paper draws both types in one panel, here one each." \
  damper "$HERE/examples/type1-sdf-paper.ini"
fig fig11b "Fig. 11, as above." \
  "Type 2's Table 2 curve and damper." \
  "as Fig. 11a." \
  damper "$HERE/examples/type2-sdf-paper.ini"
fig fig12 "Figs. 12 and 13, SDF against a constant series stiffness: stability index and lateral ride (Sperling) over conicity." \
  "the same comparison for the built-in Type 1 and Type 2, each with its Table 2 curve, at 350 km/h." \
  "loci are not repeated here (fig8b with --sdf paper draws them)." \
  compare --conicities 0.02:0.6:30
fig fig14 "Fig. 14, the hunting mode's energy distribution between carbody and bogies over speed and conicity." \
  "the kinetic-energy shares of the hunting mode (the least damped hunting-related mode) of Type 1: carbody hunting at low conicity and speed, bogie hunting above the boundary." \
  "the paper's vehicle parameters differ in detail, so the boundary moves." \
  map --speeds 100:500:41 --conicities 0.02:0.5:25 --shares

n=$(printf '%s\n' "$FIGS" | grep -c '<figure')
cat > index.html <<HTML
<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>railride: the paper's figures</title>
<style>body{font-family:sans-serif;max-width:1000px;margin:auto}figure{margin:2em 0}img{width:100%;border:1px solid #ddd}code{font-size:90%}</style>
</head><body>
<h1>railride: the paper's figures</h1>
<p>Yao, Chen, Li &amp; Li, <i>Vehicle System Dynamics</i> 61(4), 2023, regenerated from railride's built-in vehicles
($("$RR" --version)). Each figure's data is beside it as CSV.</p>
$FIGS
<script>
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; i++) if (imgs[i].complete && imgs[i].naturalWidth > 0) ok++;
  document.title = 'railride figures: ' + ok + ' of ' + imgs.length + ' images loaded';
});
</script>
</body></html>
HTML
echo "$n figures and index.html in $OUT"

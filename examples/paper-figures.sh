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

fig() {   # fig ID "CAPTION" ARGS...: railride ARGS --plot ID.svg, data kept in ID.csv
  id=$1; caption=$2; shift 2
  "$RR" "$@" --plot "$id.svg" > "$id.csv"
  cmd="railride $*"
  FIGS="$FIGS
<figure id=\"$id\"><img src=\"$id.svg\" alt=\"$id\"><figcaption><b>$id.</b> $caption<br><code>$(printf '%s' "$cmd" | sed 's/&/\&amp;/g; s/</\&lt;/g')</code></figcaption></figure>"
}

fig fig2 "Yaw damper as a Maxwell element: storage and loss stiffness and dissipation factor over frequency (paper Fig. 2)." \
  damper
fig fig5 "Vehicle stability index over the primary longitudinal stiffness and the yaw damper's series stiffness at 350 km/h, conicity 0.17 (paper Fig. 5a); the black line is zeta = 0." \
  sweep --x "primary.longitudinal_stiffness=10 kN/mm:120 kN/mm:23" --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:30" --objective "index@350,0.17"
fig fig7 "Stability map over speed and conicity (paper Fig. 7): blue stable, red unstable, black the zero line." \
  map --speeds 100:500:41 --conicities 0.02:0.5:25
fig fig8a "Root locus over speed at conicity 0.17 (paper Fig. 8a)." \
  locus --over speed --range 100:500:81 --conicity 0.17
fig fig8b "Root locus over conicity at 350 km/h (paper Fig. 8b)." \
  locus --over conicity --range 0.02:0.5:49 --speed 350
fig fig9a "Hunting limit cycles of Type 1 on the worn tread: a supercritical Hopf bifurcation (paper Fig. 9, under railride's assumed tread)." \
  bifurcation --profile worn --speeds 100:600
fig fig9b "A tread whose conicity rises with displacement makes the bifurcation subcritical: unstable cycles (hollow) down to a fold, the nonlinear critical speed." \
  bifurcation "$HERE/examples/type1-rising-tread.ini" --speeds 100:620
fig fig10 "Stability index over conicity and the yaw damper's series stiffness at 350 km/h: the best stiffness rises with conicity (paper Fig. 10)." \
  sweep --x conicity=0.05:0.4:8 --y "yaw_damper.series_stiffness=1 MN/m:30 MN/m:30" --objective index@350
fig fig12 "Frequency-dependent series stiffness (SDF) against a constant one: stability index and Sperling index over conicity, Type 1 and Type 2 (paper Figs. 12 and 13)." \
  compare --conicities 0.02:0.6:30
fig fig14 "Carbody floor lateral acceleration PSD at 350 km/h for conicities 0.05, 0.17 and 0.40 by the pseudo-excitation method (paper Fig. 14)." \
  ride --speed 350 --conicity 0.05,0.17,0.40

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

# SPDX-License-Identifier: MIT
# Lag expansion of the conditional mean (aenl moments --expansion): the restoring-force curve
# (acceleration against the noise-free position, per direction) on top, the phase portrait
# (velocity against position) below. Variables: in (CSV), out (the figure, in the format aenl_fmt names), title, xlabel.
if (!exists("title")) title = ''
if (!exists("xlabel")) xlabel = 'x'
aenl_w = 900; aenl_h = 900; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top right
set multiplot layout 2,1 title title noenhanced
set xlabel sprintf('position p = E(s | X = x), %s', xlabel) noenhanced
set ylabel 'acceleration a(p), per sample^2' noenhanced
plot in using ($1 == 1 ? $3 : NaN):5 with lines lw 2 title 'rising', \
     in using ($1 == 2 ? $3 : NaN):5 with lines lw 2 title 'falling', \
     in using ($1 == 0 ? $3 : NaN):5 with lines lw 2 dt 2 title 'all pairs'
set ylabel 'velocity v(p), per sample' noenhanced
plot in using ($1 == 1 ? $3 : NaN):4 with lines lw 2 title 'rising', \
     in using ($1 == 2 ? $3 : NaN):4 with lines lw 2 title 'falling'
unset multiplot

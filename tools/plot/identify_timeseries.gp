# SPDX-License-Identifier: MIT
# `aenl identify --plot`, figure 1 of a channel: the record. Top: the whole record as a min/max
# envelope over bins of `per_bin` samples (bounded size whatever the record's length); bottom: the
# last samples at full rate. Identified switching points are dashed horizontal lines.
# Variables: env (CSV t,lo,hi), detail (CSV t,x), out (the figure, in the format aenl_fmt names); optional: title, ylabel, marks
# ("x1 x2 ..."), per_bin (samples per envelope bin), tlabel (x-axis: the time column's name).
if (!exists("title")) title = ''
if (!exists("ylabel")) ylabel = 'x'
if (!exists("marks")) marks = ''
if (!exists("per_bin")) per_bin = '1'
if (!exists("tlabel")) tlabel = 'time'
aenl_w = 1000; aenl_h = 800; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top right opaque
set lmargin 12
set multiplot layout 2,1 title title noenhanced
do for [m in marks] {
  set arrow from graph 0, first m+0 to graph 1, first m+0 nohead dt 2 lw 1.5 lc rgb '#aa0000'
  set label sprintf('%.4g', m+0) at graph 0.005, first m+0 left offset 0, 0.5 front tc rgb '#aa0000' noenhanced
}
set format x '%g'
set format y '%g'
marktitle = words(marks) > 0 ? 'switching points' : ''
set xlabel tlabel noenhanced
set ylabel ylabel noenhanced
envtitle = (per_bin + 0 > 1) ? sprintf('min/max per %s samples', per_bin) : 'samples'
plot env using 1:2:3 with filledcurves fc rgb '#9fb6dd' fs solid 0.6 noborder title envtitle, \
     env using 1:2 with lines lw 1 lc rgb '#1f4e9c' notitle, \
     env using 1:3 with lines lw 1 lc rgb '#1f4e9c' notitle, \
     NaN with lines dt 2 lw 1.5 lc rgb '#aa0000' title marktitle
set ylabel sprintf('%s (last samples)', ylabel) noenhanced
plot detail using 1:2 with lines lw 1.2 lc rgb '#1f4e9c' title 'full rate', \
     NaN with lines dt 2 lw 1.5 lc rgb '#aa0000' title marktitle
unset multiplot

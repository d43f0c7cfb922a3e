# SPDX-License-Identifier: MIT
# `aenl identify --plot`, figure 3 of a channel: the restoring-force points the classifier fits
# (lag expansion of the conditional mean: acceleration against the noise-free position), all pairs
# and split by the direction of motion; flat across a freeplay gap, shifted between rising and
# falling for hysteresis, curved for polynomial stiffness. Switching points: dashed vertical lines.
# Variables: in (CSV dir,position,accel: dir 0 all, 1 rising, 2 falling), out (the figure, in the format aenl_fmt names); optional:
# title, xlabel, ylabel (the acceleration's unit), marks ("x1 x2 ...").
if (!exists("title")) title = ''
if (!exists("xlabel")) xlabel = 'x'
if (!exists("marks")) marks = ''
if (!exists("ylabel")) ylabel = 'acceleration a(p), per sample^2'
aenl_w = 900; aenl_h = 700; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top right
set lmargin 12
set title title noenhanced
do for [m in marks] {
  set arrow from first m+0, graph 0 to first m+0, graph 1 nohead dt 2 lw 1.5 lc rgb '#aa0000'
  set label sprintf(' %.4g', m+0) at first m+0, graph 0.04 left front tc rgb '#aa0000' noenhanced
}
set format x '%g'
set format y '%g'
marktitle = words(marks) > 0 ? 'switching points' : ''
set xlabel sprintf('position p = E(s | X = x), %s', xlabel) noenhanced
set ylabel ylabel noenhanced
plot in using ($1 == 1 ? $2 : NaN):3 with linespoints pt 7 ps 0.6 lw 1.2 lc rgb '#c0392b' title 'rising', \
     in using ($1 == 2 ? $2 : NaN):3 with linespoints pt 5 ps 0.6 lw 1.2 lc rgb '#2471a3' title 'falling', \
     in using ($1 == 0 ? $2 : NaN):3 with linespoints pt 6 ps 0.8 lw 2 lc rgb '#222222' title 'all pairs', \
     NaN with lines dt 2 lw 1.5 lc rgb '#aa0000' title marktitle

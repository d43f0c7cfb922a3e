# SPDX-License-Identifier: MIT
# Conditional mean (top) and variance (bottom) per lag, as in the paper's Figs. 5-9.
# Variables: in (CSV from `aenl moments`), out (the figure, in the format aenl_fmt names), lags ("1 10 30"), title, xlabel;
# optional: marks ("x1 x2 ...": switching points drawn as vertical lines, each labelled with its value).
if (!exists("title")) title = ''
if (!exists("xlabel")) xlabel = 'x'
if (!exists("marks")) marks = ''
aenl_w = 900; aenl_h = 900; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top left
set multiplot layout 2,1 title title noenhanced
do for [m in marks] {
  set arrow from first m+0, graph 0 to first m+0, graph 1 nohead dt 2 lw 1.5 lc rgb '#aa0000'
  set label sprintf(' %.4g', m+0) at first m+0, graph 0.04 left front tc rgb '#aa0000' noenhanced
}
set format x '%g'
set format y '%g'
set xlabel xlabel noenhanced
set ylabel sprintf('E(X_n | X_{n-L} = %s)', xlabel) noenhanced
plot for [l in lags] in using 2:($1 == l+0 ? $3 : NaN) with lines lw 2 title sprintf('L = %s', l)
set ylabel sprintf('Var(X_n | X_{n-L} = %s)', xlabel) noenhanced
plot for [l in lags] in using 2:($1 == l+0 ? $4 : NaN) with lines lw 2 title sprintf('L = %s', l)
unset multiplot

# SPDX-License-Identifier: MIT
# `aenl diagnose`: Welch power spectral density of one channel, measured, baseline and updated.
# Variables: in (spectrum_<ch>.csv: f,measured,baseline,updated), out (the figure, in the format aenl_fmt names); optional: title.
if (!exists("title")) title = ''
aenl_w = 900; aenl_h = 500; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set logscale xy
set key top right
set title title noenhanced
set xlabel 'frequency (cycles per model time unit)'
set ylabel 'PSD'
plot in using 1:($2 > 0 ? $2 : NaN) with lines lw 2 lc rgb '#1f4e9c' title 'measured', \
     in using 1:($3 > 0 ? $3 : NaN) with lines lw 1.5 dt 2 lc rgb '#606060' title 'baseline', \
     in using 1:($4 > 0 ? $4 : NaN) with lines lw 1.5 lc rgb '#2a9c1f' title 'updated'

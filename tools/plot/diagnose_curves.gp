# SPDX-License-Identifier: MIT
# `aenl diagnose`: conditional mean (rising and falling motion, top) and conditional standard
# deviation (bottom) of one channel at the middle lag, measured (with a +-2 kernel-SE band),
# baseline and updated model overlaid.
# Variables: in (curves_<ch>.csv), out (the figure, in the format aenl_fmt names); optional: title, xlabel.
if (!exists("title")) title = ''
if (!exists("xlabel")) xlabel = 'x'
aenl_w = 900; aenl_h = 900; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top left
set multiplot layout 2,1 title title noenhanced
set xlabel xlabel noenhanced
set ylabel sprintf('E(X_n | X_{n-L} = %s)', xlabel) noenhanced
plot in using 1:3:4 with filledcurves lc rgb '#d0d8f0' title 'measured +-2 SE (rising)', \
     in using 1:8:9 with filledcurves lc rgb '#f0d8d0' title 'measured +-2 SE (falling)', \
     in using 1:2 with lines lw 2 lc rgb '#1f4e9c' title 'measured rising', \
     in using 1:7 with lines lw 2 lc rgb '#9c1f1f' title 'measured falling', \
     in using 1:5 with lines lw 1.5 dt 2 lc rgb '#606060' title 'baseline rising', \
     in using 1:10 with lines lw 1.5 dt 3 lc rgb '#606060' title 'baseline falling', \
     in using 1:6 with lines lw 1.5 lc rgb '#2a9c1f' title 'updated rising', \
     in using 1:11 with lines lw 1.5 dt 4 lc rgb '#2a9c1f' title 'updated falling'
set ylabel sprintf('Std(X_n | X_{n-L} = %s), rising', xlabel) noenhanced
plot in using 1:12 with lines lw 2 lc rgb '#1f4e9c' title 'measured', \
     in using 1:13 with lines lw 1.5 dt 2 lc rgb '#606060' title 'baseline', \
     in using 1:14 with lines lw 1.5 lc rgb '#2a9c1f' title 'updated'
unset multiplot

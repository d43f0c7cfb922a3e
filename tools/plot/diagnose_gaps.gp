# SPDX-License-Identifier: MIT
# `aenl diagnose`: the gap per channel and in total before and after the update, with the
# replicate noise floor (README "Diagnose: the gap metric"), on a log scale.
# Variables: in (gaps.csv), out (the figure, in the format aenl_fmt names); optional: title.
if (!exists("title")) title = ''
aenl_w = 800; aenl_h = 500; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set grid ytics
set logscale y
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set key top right
set title title noenhanced
set ylabel 'gap'
plot in using 2:xtic(1) lc rgb '#909090' title 'before', \
     '' using 4 lc rgb '#2a9c1f' title 'after', \
     '' using 5 lc rgb '#d0d8f0' title 'noise floor (after)'

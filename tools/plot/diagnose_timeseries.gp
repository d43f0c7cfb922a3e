# SPDX-License-Identifier: MIT
# `aenl diagnose`: time histories at the end of the record, one panel per channel, measured,
# baseline and updated model (the simulated ones with the record's noise level).
# Variables: in (timeseries.csv: t, then <ch>_measured,<ch>_baseline,<ch>_updated per channel),
# out (the figure, in the format aenl_fmt names); optional: title.
if (!exists("title")) title = ''
# names are split at commas only (a channel's name may hold spaces)
header_cmd = sprintf("head -n 1 '%s' | tr -d '\\r'", in)
nch = (int(system(header_cmd . " | awk -F, '{print NF}'")) - 1) / 3
colname(i) = system(sprintf("%s | cut -d, -f%d", header_cmd, i))
aenl_w = 1000; aenl_h = (260 * nch + 80); aenl_fs = 10
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top right horizontal
set lmargin 12
set multiplot layout nch, 1 title title noenhanced
do for [c = 0:nch-1] {
    name = colname(2 + 3 * c)
    set ylabel name[1:strstrt(name, '_')-1] noenhanced
    if (c == nch - 1) { set xlabel 'time (model unit)' } else { unset xlabel }
    plot in using 1:(column(2 + 3 * c)) with lines lw 1 lc rgb '#1f4e9c' title 'measured', \
         in using 1:(column(3 + 3 * c)) with lines lw 1 lc rgb '#909090' title 'baseline', \
         in using 1:(column(4 + 3 * c)) with lines lw 1 lc rgb '#2a9c1f' title 'updated'
}
unset multiplot

# SPDX-License-Identifier: MIT
# Every channel of a time-series CSV (`aenl simulate` output or a measured record) against the
# first column, one stacked panel per channel, sharing the time axis.
# Variables: in (CSV with a header row), out (the figure), aenl_fmt (png, svg or pdf) and
# aenl_term_dir (this folder: terminal.gp); optional: title, tcol_label (x-axis label, default:
# the first column's name), width (pixels, default 1000).
# Usage: gnuplot -e "in='f.csv'; out='f.png'; aenl_fmt='png'; aenl_term_dir='DIR'" timeseries.gp
if (!exists("title")) title = ''
if (!exists("width")) width = 1000
# Header row: the first line that is not a '#' comment; names are split at commas only (a name
# may hold spaces: "Time [s]").
header_cmd = sprintf("grep -v '^#' '%s' 2>/dev/null | head -n 1 | tr -d '\\r'", in)
ncol = int(system(header_cmd . " | awk -F, '{print NF}'"))
colname(i) = system(sprintf("%s | cut -d, -f%d", header_cmd, i))
if (ncol < 2) { print sprintf("timeseries.gp: %s has no data columns", in); exit }
if (!exists("tcol_label")) tcol_label = colname(1)
npanel = ncol - 1
panel_h = (npanel > 4) ? 180 : 240
aenl_w = width; aenl_h = (panel_h * npanel + 80); aenl_fs = 10
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile commentschars '#'
set datafile missing 'nan'
set key off
set grid
set lmargin 12
set rmargin 3
set multiplot layout npanel, 1 title title noenhanced
do for [i = 2:ncol] {
    set tmargin (i == 2 ? 2 : 0.5)
    set bmargin (i == ncol ? 3.5 : 0.5)
    if (i == ncol) { set xlabel tcol_label noenhanced; set format x '%g' } else { unset xlabel; set format x '' }
    set ylabel colname(i) noenhanced
    plot in every ::1 using 1:i with lines lw 1.2 lc rgb '#1f4e9c'
}
unset multiplot

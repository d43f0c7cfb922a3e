# SPDX-License-Identifier: MIT
# Every channel of a time-series CSV (`aenl simulate` output or a measured record) against the
# first column, one stacked panel per channel, sharing the time axis.
# Variables: in (CSV with a header row), out (PNG); optional: title, tcol_label (x-axis label,
# default: the first column's name), width (pixels, default 1000).
# Usage: gnuplot -e "in='file.csv'; out='file.png'; title='...'" tools/plot/timeseries.gp
if (!exists("title")) title = ''
if (!exists("width")) width = 1000
# Header row: the first line that is not a '#' comment, commas turned into spaces.
hdr = system(sprintf("grep -v '^#' '%s' 2>/dev/null | head -n 1 | tr -d '\\r' | tr ',' ' '", in))
ncol = words(hdr)
if (ncol < 2) { print sprintf("timeseries.gp: %s has no data columns", in); exit }
if (!exists("tcol_label")) tcol_label = word(hdr, 1)
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
    set ylabel word(hdr, i) noenhanced
    plot in every ::1 using 1:i with lines lw 1.2 lc rgb '#1f4e9c'
}
unset multiplot

# SPDX-License-Identifier: MIT
# `aenl identify --plot` (the test), figure 2 of a channel: the force each law adds, as the test
# fitted it at its best switching points, against the channel's position; the hysteresis law's
# rising and falling branches apart. Each law is drawn less its straight-line part over the
# record (the linear model's stiffness and offset, which the test takes as nuisance). One scale
# for the three laws, oriented so that a force that raises the frequency grows with position (a
# hardening spring's shape); its unit is the linear model's scaled state per sample: read the
# shapes and how they differ, not the values.
# The named law (or the best one when undetermined) is drawn thick; its switching points are
# dashed vertical lines, labelled with their values, their 95 % profile intervals shaded.
# Variables: in (CSV position,polynomial,freeplay,hyst_rising,hyst_falling), out (the figure,
# format from aenl_fmt), best (polynomial, freeplay or hysteresis); optional: title, xlabel,
# marks ("x1 x2 ..."), spans ("lo1 hi1 lo2 hi2 ...").
if (!exists("title")) title = ''
if (!exists("xlabel")) xlabel = 'x'
if (!exists("marks")) marks = ''
if (!exists("spans")) spans = ''
if (!exists("best")) best = ''
aenl_w = 900; aenl_h = 700; aenl_fs = 11
load aenl_term_dir.'/terminal.gp'
set output out
set datafile separator comma
set datafile columnheaders
set datafile missing 'nan'
set grid
set key top left opaque
set lmargin 12
set format x '%g'
set format y '%g'
set title title noenhanced
nspan = words(spans) / 2
do for [k = 1:nspan] {
  set object k rect from first word(spans, 2*k-1)+0, graph 0 to first word(spans, 2*k)+0, graph 1 \
      behind fc rgb '#f2d7d5' fs solid 0.5 noborder
}
k = 0
do for [m in marks] {
  k = k + 1
  set arrow from first m+0, graph 0 to first m+0, graph 1 nohead dt 2 lw 1.5 lc rgb '#aa0000'
  set label sprintf(' %.4g', m+0) at first m+0, graph (k % 2 ? 0.04 : 0.09) left front \
      tc rgb '#aa0000' noenhanced
}
set xlabel sprintf('position of %s', xlabel) noenhanced
set ylabel 'force the law adds beyond a straight line (one scale for the three)' noenhanced
lw(name) = (name eq best) ? 3.0 : 1.2
marktitle = words(marks) > 0 ? sprintf('switching points of the %s law (95 %% intervals shaded)', best) : ''
plot in using 1:2 with lines lw lw('polynomial') lc rgb '#7d3c98' title 'polynomial', \
     in using 1:3 with lines lw lw('freeplay') lc rgb '#1e8449' title 'freeplay', \
     in using 1:4 with lines lw lw('hysteresis') lc rgb '#c0392b' title 'hysteresis, rising', \
     in using 1:5 with lines lw lw('hysteresis') lc rgb '#2471a3' title 'hysteresis, falling', \
     NaN with lines dt 2 lw 1.5 lc rgb '#aa0000' title marktitle

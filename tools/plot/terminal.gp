# SPDX-License-Identifier: MIT
# The terminal of every figure, chosen from the output's extension (aenl_fmt: png, svg or pdf,
# set by aenl), aenl_w x aenl_h pixels (a PDF at 100 pixels to the inch), font size aenl_fs.
aenl_font = sprintf(',%d', aenl_fs)
if (aenl_fmt eq 'svg') {
  set terminal svg size aenl_w, aenl_h enhanced font aenl_font background rgb 'white'
} else {
  if (aenl_fmt eq 'pdf') {
    set terminal pdfcairo size (aenl_w / 100.0), (aenl_h / 100.0) enhanced font aenl_font
  } else {
    set terminal pngcairo size aenl_w, aenl_h enhanced font aenl_font
  }
}

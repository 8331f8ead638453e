# Written by 'splatcl bench plot'; rerun with: gnuplot docs/bench/plots/devices-csm/plots.gp

set terminal pngcairo size 1708,800 noenhanced font ",9"
set linetype 1 lc rgb "#1f77b4" lw 2 pt 1
set linetype 2 lc rgb "#ff7f0e" lw 2 pt 2
set linetype 3 lc rgb "#2ca02c" lw 2 pt 3
set linetype 4 lc rgb "#d62728" lw 2 pt 4
set linetype 5 lc rgb "#9467bd" lw 2 pt 5
set linetype 6 lc rgb "#8c564b" lw 2 pt 6
set linetype 7 lc rgb "#e377c2" lw 2 pt 7
set linetype 8 lc rgb "#7f7f7f" lw 2 pt 1
set linetype 9 lc rgb "#bcbd22" lw 2 pt 2
set linetype 10 lc rgb "#17becf" lw 2 pt 3
set linetype 11 lc rgb "#393b79" lw 2 pt 4
set linetype 12 lc rgb "#e7ba52" lw 2 pt 5
set linetype 13 lc rgb "#637939" lw 2 pt 6
set linetype 14 lc rgb "#ad494a" lw 2 pt 7
set linetype 15 lc rgb "#7b4173" lw 2 pt 1
set linetype 16 lc rgb "#000000" lw 2 pt 2
set linetype cycle 16
set output "docs/bench/plots/devices-csm/throughput-csm.png.part"
set title "bench csm: throughput per case and implementation, higher is better"
set datafile separator "\t"
set datafile missing "?"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set logscale y
set ylabel "throughput (units per second, log scale)"
set grid ytics
set xtics rotate by 30 right
set bmargin 17
set lmargin 40
set key outside right top
plot for [i=2:13] "docs/bench/plots/devices-csm/throughput-csm.dat" using i:xtic(1) title columnhead(i)
unset output
reset

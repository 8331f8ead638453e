# Written by 'splatcl bench plot'; rerun with: gnuplot docs/bench/plots/primitives-scaling-size/plots.gp

set terminal pngcairo size 1564,800 noenhanced font ",9"
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
set output "docs/bench/plots/primitives-scaling-size/throughput-primitives.png.part"
set title "bench primitives: throughput per case and implementation, higher is better" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
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
plot for [i=2:9] "docs/bench/plots/primitives-scaling-size/throughput-primitives.dat" using i:xtic(1) title columnhead(i)
unset output
reset

set terminal pngcairo size 1200,1148 noenhanced font ",9"
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
set output "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.png.part"
set datafile separator "\t"
set grid
set key outside below
set title "bench primitives: throughput against problem size (x2 steps)" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
set logscale xy 2
set xlabel "problem size"
set ylabel "throughput (units per second)"
set format y "%.3g"
plot "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 0 using 1:2 with linespoints title "scan-exclusive: opencl (cpu shape) [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 1 using 1:2 with linespoints title "scan-exclusive: opencl (gpu shape) [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 2 using 1:2 with linespoints title "scan-exclusive: reference [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 3 using 1:2 with linespoints title "compact-flagged: opencl (cpu shape) [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 4 using 1:2 with linespoints title "compact-flagged: opencl (gpu shape) [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 5 using 1:2 with linespoints title "compact-flagged: reference [elements/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 6 using 1:2 with linespoints title "compact-unique: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 7 using 1:2 with linespoints title "compact-unique: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 8 using 1:2 with linespoints title "compact-unique: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 9 using 1:2 with linespoints title "compact-unique: std [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 10 using 1:2 with linespoints title "compact-unique: boost.compute [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 11 using 1:2 with linespoints title "radix-sort-u32 bits=20: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 12 using 1:2 with linespoints title "radix-sort-u32 bits=20: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 13 using 1:2 with linespoints title "radix-sort-u32 bits=20: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 14 using 1:2 with linespoints title "radix-sort-u32 bits=20: std [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 15 using 1:2 with linespoints title "radix-sort-u32 bits=20: boost.compute [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 16 using 1:2 with linespoints title "radix-sort-u32 bits=32: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 17 using 1:2 with linespoints title "radix-sort-u32 bits=32: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 18 using 1:2 with linespoints title "radix-sort-u32 bits=32: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 19 using 1:2 with linespoints title "radix-sort-u32 bits=32: std [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 20 using 1:2 with linespoints title "radix-sort-u32 bits=32: boost.compute [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 21 using 1:2 with linespoints title "radix-sort-kv bits=32: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 22 using 1:2 with linespoints title "radix-sort-kv bits=32: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 23 using 1:2 with linespoints title "radix-sort-kv bits=32: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 24 using 1:2 with linespoints title "radix-sort-u64 bits=64: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 25 using 1:2 with linespoints title "radix-sort-u64 bits=64: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 26 using 1:2 with linespoints title "radix-sort-u64 bits=64: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 27 using 1:2 with linespoints title "sort-unique bits=20: opencl (cpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 28 using 1:2 with linespoints title "sort-unique bits=20: opencl (gpu shape) [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 29 using 1:2 with linespoints title "sort-unique bits=20: reference [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 30 using 1:2 with linespoints title "sort-unique bits=20: std [keys/s]", \
     "docs/bench/plots/primitives-scaling-size/scaling-size-primitives.dat" index 31 using 1:2 with linespoints title "sort-unique bits=20: boost.compute [keys/s]"
unset output
reset

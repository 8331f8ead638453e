# Written by 'splatcl bench plot'; rerun with: gnuplot docs/bench/plots/cluster-scaling-size/plots.gp

set terminal pngcairo size 1800,800 noenhanced font ",9"
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
set output "docs/bench/plots/cluster-scaling-size/throughput-cluster.png.part"
set title "bench cluster: throughput per case and implementation, higher is better" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
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
plot for [i=2:19] "docs/bench/plots/cluster-scaling-size/throughput-cluster.dat" using i:xtic(1) title columnhead(i)
unset output
reset

set terminal pngcairo size 1200,1120 noenhanced font ",9"
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
set output "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.png.part"
set datafile separator "\t"
set grid
set key outside below
set title "bench cluster: throughput against problem size (x2 steps)" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
set logscale xy 2
set xlabel "problem size"
set ylabel "throughput (units per second)"
set format y "%.3g"
plot "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 0 using 1:2 with linespoints title "keys: opencl (cpu shape) [pixels/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 1 using 1:2 with linespoints title "keys: opencl (gpu shape) [pixels/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 2 using 1:2 with linespoints title "keys: reference [pixels/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 3 using 1:2 with linespoints title "compact: opencl global-sort (cpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 4 using 1:2 with linespoints title "compact: opencl global-sort (gpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 5 using 1:2 with linespoints title "compact: opencl tile-sort (cpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 6 using 1:2 with linespoints title "compact: opencl tile-sort (gpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 7 using 1:2 with linespoints title "compact: opencl bitmask (cpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 8 using 1:2 with linespoints title "compact: opencl bitmask (gpu shape) [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 9 using 1:2 with linespoints title "compact: reference [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 10 using 1:2 with linespoints title "compact: std [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 11 using 1:2 with linespoints title "compact: boost.compute [keys/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 12 using 1:2 with linespoints title "bounds: opencl (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 13 using 1:2 with linespoints title "bounds: opencl (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 14 using 1:2 with linespoints title "bounds: reference [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 15 using 1:2 with linespoints title "assign-lights lights=1024: opencl brute (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 16 using 1:2 with linespoints title "assign-lights lights=1024: opencl brute (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 17 using 1:2 with linespoints title "assign-lights lights=1024: opencl bvh (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 18 using 1:2 with linespoints title "assign-lights lights=1024: opencl bvh (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 19 using 1:2 with linespoints title "assign-lights lights=1024: reference [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 20 using 1:2 with linespoints title "assign-lights lights=16384: opencl brute (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 21 using 1:2 with linespoints title "assign-lights lights=16384: opencl brute (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 22 using 1:2 with linespoints title "assign-lights lights=16384: opencl bvh (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 23 using 1:2 with linespoints title "assign-lights lights=16384: opencl bvh (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 24 using 1:2 with linespoints title "assign-lights lights=16384: reference [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 25 using 1:2 with linespoints title "assign-lights lights=262144: opencl brute (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 26 using 1:2 with linespoints title "assign-lights lights=262144: opencl brute (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 27 using 1:2 with linespoints title "assign-lights lights=262144: opencl bvh (cpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 28 using 1:2 with linespoints title "assign-lights lights=262144: opencl bvh (gpu shape) [clusters/s]", \
     "docs/bench/plots/cluster-scaling-size/scaling-size-cluster.dat" index 29 using 1:2 with linespoints title "assign-lights lights=262144: reference [clusters/s]"
unset output
reset

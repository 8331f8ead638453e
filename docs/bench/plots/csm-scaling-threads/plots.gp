# Written by 'splatcl bench plot'; rerun with: gnuplot docs/bench/plots/csm-scaling-threads/plots.gp

set terminal pngcairo size 1348,800 noenhanced font ",9"
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
set output "docs/bench/plots/csm-scaling-threads/throughput-csm.png.part"
set title "bench csm: throughput per case and implementation, higher is better" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
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
plot for [i=2:10] "docs/bench/plots/csm-scaling-threads/throughput-csm.dat" using i:xtic(1) title columnhead(i)
unset output
reset

set terminal pngcairo size 1200,910 noenhanced font ",9"
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
set output "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.png.part"
set datafile separator "\t"
set grid
set key outside below
set title "bench csm: speedup over one thread (POCL_MAX_PTHREAD_COUNT)" . "\n" . "OpenCL device pthread-skylake-avx512-Intel(R) Xeon(R) Processor"
set xlabel "threads"
set ylabel "speedup over 1 thread"
set xtics 1
plot "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 0 using 1:2 with linespoints title "capture model=stanford-bunny res=128: reference raycast (1048576 rays)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 1 using 1:2 with linespoints title "capture model=stanford-bunny res=128: opencl raycast (1048576 rays)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 2 using 1:2 with linespoints title "capture model=stanford-bunny res=128: reference raster (1048576 rays)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 3 using 1:2 with linespoints title "capture model=stanford-bunny res=128: opencl raster (1048576 rays)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 4 using 1:2 with linespoints title "capture model=stanford-bunny res=128: embree rtcIntersect16 3.13.5 (1048576 rays)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 5 using 1:2 with linespoints title "compress model=stanford-bunny res=128: reference (1048576 samples)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 6 using 1:2 with linespoints title "compress model=stanford-bunny res=128: opencl (1048576 samples)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 7 using 1:2 with linespoints title "visibility model=stanford-bunny maps=1024 res=64: reference (1048576 queries)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 8 using 1:2 with linespoints title "visibility model=stanford-bunny maps=1024 res=64: opencl (1048576 queries)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 9 using 1:2 with linespoints title "visibility-host-io model=stanford-bunny maps=1024 res=64: opencl (1048576 queries)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 10 using 1:2 with linespoints title "ao model=stanford-bunny maps=1024 res=64: reference (1179648 samples)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 11 using 1:2 with linespoints title "ao model=stanford-bunny maps=1024 res=64: opencl (1179648 samples)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 12 using 1:2 with linespoints title "stream-copy: std::thread copy loop (536870912 bytes)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 13 using 1:2 with linespoints title "stream-copy: std::thread memcpy (536870912 bytes)", \
     "docs/bench/plots/csm-scaling-threads/scaling-threads-csm.dat" index 14 using 1:2 with linespoints title "stream-copy: opencl (536870912 bytes)"
unset output
reset

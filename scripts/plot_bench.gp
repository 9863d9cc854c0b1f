# Log-log plot of penumbra-bench's ray rates against scene size.
#
# penumbra-bench --plot FILE.png writes FILE.tsv and runs this script itself
# (it is compiled into the program). To redraw from a kept data file:
#   gnuplot -e "datafile='docs/bench_rays.tsv'; outfile='bench.png'" scripts/plot_bench.gp
#
# The data file holds nine blocks, one per accelerator (embree, raw_embree,
# naive) and ray kind (camera, shadow, incoherent), in that order; the first
# line of a block is its title, then "triangles <TAB> Mrays/s" rows.

if (!exists("datafile")) datafile = 'bench_rays.tsv'
if (!exists("outfile")) outfile = 'bench_rays.png'
if (!exists("plottitle")) plottitle = 'penumbra-bench'

set terminal pngcairo size 1000,700 enhanced font 'sans,11'
set output outfile
set title plottitle noenhanced
set logscale xy
set yrange [*:3e8]
set autoscale xfix
set offsets graph 0.03, graph 0.03, 0, 0
set format x '10^{%L}'
set format y '10^{%L}'
set xlabel 'triangles in the scene'
set ylabel 'rays per second'
set grid xtics ytics mxtics mytics lc rgb '#dddddd'
set key inside top right maxrows 3 samplen 3 spacing 1.1 noenhanced opaque box lc rgb '#cccccc'
set key autotitle columnheader

# Colour = ray kind, dash and point shape = accelerator.
kind_colour(i) = word('#1f77b4 #d62728 #2ca02c', i % 3 + 1)
plot for [i=0:8] datafile index i using 1:($2 * 1e6) \
    with linespoints lw 2 lc rgb kind_colour(i) dt 1 + i / 3 pt (i / 3 * 2 + 5) pointsize 1.2

# gnuplot script written by rtsdf bench --sweep; rerun with: gnuplot sweep.gp (in this folder)
set terminal pngcairo size 1100,700 noenhanced font 'sans,11'
set datafile separator '\t'
set grid
set key outside right top
set output '../pareto.png'
set title "default.json: time vs accuracy (lower left is better; the front skips points with > 1% wrong signs)"
set key outside right top
set logscale x
unset logscale y
set xlabel 'time per frame (ms, log scale; anchors: CPU wall time)'
set ylabel 'mean |error| (fine voxels)'
plot 'pareto_front.tsv' using 1:2 with lines lw 2 lc rgb '#888888' title "Pareto front", \
     'pareto_front.tsv' using 1:2:3 with labels left offset 0.6,0.5 font ',8' tc rgb '#444444' notitle, \
     'pareto_sizes.tsv' using 1:2 with points pt 7 ps 1.3 title "sizes points", \
     'pareto_band.tsv' using 1:2 with points pt 7 ps 1.3 title "band points", \
     'pareto_alpha.tsv' using 1:2 with points pt 7 ps 1.3 title "alpha points", \
     'pareto_frames.tsv' using 1:2 with points pt 7 ps 1.3 title "frames points", \
     'pareto_jfa.tsv' using 1:2 with points pt 7 ps 1.3 title "jfa points", \
     'pareto_bruteforce.tsv' using 1:2 with points pt 9 ps 2.2 lc rgb '#d62728' title "brute force: d = inf (anchor)", \
     'pareto_openvdb.tsv' using 1:2 with points pt 5 ps 2.2 lc rgb '#000000' title "OpenVDB meshToLevelSet (anchor)", \
     'pareto_exact.tsv' using 1:2 with points pt 13 ps 2.4 lc rgb '#2ca02c' title "exact reference (anchor)"
set output '../time_vs_work.png'
set title "default.json: how cost grows with the work"
set logscale xy
set xlabel 'fine voxels refined (ray mask; anchors: voxels in their band), log'
set ylabel 'time per frame (ms, log)'
plot 'work_1.tsv' using 1:2 with points pt 7 ps 1.3 title "rays x=0", \
     'work_2.tsv' using 1:2 with points pt 7 ps 1.3 title "rays x=1", \
     'work_3.tsv' using 1:2 with points pt 7 ps 1.3 title "rays x=5", \
     'work_4.tsv' using 1:2 with points pt 7 ps 1.3 title "rays x=10", \
     'work_5.tsv' using 1:2 with points pt 7 ps 1.3 title "closest", \
     'work_openvdb.tsv' using 1:2 with linespoints pt 5 ps 1.8 lw 2 lc rgb '#000000' title "OpenVDB meshToLevelSet", \
     'work_exact.tsv' using 1:2 with linespoints pt 13 ps 1.8 lw 2 lc rgb '#2ca02c' title "exact reference"
set output '../error_vs_frames.png'
set title "default.json: error over frames"
set key inside top right opaque box
unset logscale
set logscale x 2
set xlabel 'frame (static: frames accumulated)'
set ylabel 'mean |error| vs the exact field of that frame (fine voxels)'
plot 'frames_static.tsv' using 1:2 with linespoints pt 7 lw 2 title "static scene: error after N frames (x=1, alpha 0.95)", \
     'frames_dynamic_1.tsv' using 1:2 with linespoints pt 6 lw 2 title "moving scene: S rays x=5 d=0.1 alpha=0.5 frames=16", \
     'frames_dynamic_2.tsv' using 1:2 with linespoints pt 6 lw 2 title "moving scene: S rays x=5 d=0.1 alpha=0.95 frames=16", \
     'frames_dynamic_3.tsv' using 1:2 with linespoints pt 6 lw 2 title "moving scene: S closest d=0.1 alpha=0.95 frames=16"

set terminal pngcairo noenhanced size 1400,1000 font 'sans,11'
set style data histogram
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set logscale y
set grid ytics
set key outside right top vertical
set xtics nomirror
set datafile missing '?'
set xrange [-0.6:1.6]
set output 'doc/img/ycbv_video0000_crops_mean.png'
set multiplot layout 2,1 title 'Mean error per group and method (ycbv_video0000_crops; log scale)'
set ylabel '(a) translation error (mm)'
plot 'doc/bench/ycbv_video0000_crops_plot.dat' using 2:xtic(1) title 'icf-fast', 'doc/bench/ycbv_video0000_crops_plot.dat' using 6 title 'icf-thesis', 'doc/bench/ycbv_video0000_crops_plot.dat' using 10 title 'icf-fast+sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 14 title 'icf-sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 18 title 'icp-p2p', 'doc/bench/ycbv_video0000_crops_plot.dat' using 22 title 'icp-p2plane', 'doc/bench/ycbv_video0000_crops_plot.dat' using 26 title 'sacia+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 30 title 'prerej+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 34 title 'o3d-ransac+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 38 title 'o3d-fgr+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 42 title 'ppf+icp'
set ylabel '(b) rotation error (deg)'
plot 'doc/bench/ycbv_video0000_crops_plot.dat' using 4:xtic(1) title 'icf-fast', 'doc/bench/ycbv_video0000_crops_plot.dat' using 8 title 'icf-thesis', 'doc/bench/ycbv_video0000_crops_plot.dat' using 12 title 'icf-fast+sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 16 title 'icf-sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 20 title 'icp-p2p', 'doc/bench/ycbv_video0000_crops_plot.dat' using 24 title 'icp-p2plane', 'doc/bench/ycbv_video0000_crops_plot.dat' using 28 title 'sacia+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 32 title 'prerej+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 36 title 'o3d-ransac+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 40 title 'o3d-fgr+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 44 title 'ppf+icp'
unset multiplot
set output 'doc/img/ycbv_video0000_crops_std.png'
set multiplot layout 2,1 title 'Standard deviation of the error per group and method (ycbv_video0000_crops; log scale)'
set ylabel '(a) translation error (mm)'
plot 'doc/bench/ycbv_video0000_crops_plot.dat' using 3:xtic(1) title 'icf-fast', 'doc/bench/ycbv_video0000_crops_plot.dat' using 7 title 'icf-thesis', 'doc/bench/ycbv_video0000_crops_plot.dat' using 11 title 'icf-fast+sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 15 title 'icf-sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 19 title 'icp-p2p', 'doc/bench/ycbv_video0000_crops_plot.dat' using 23 title 'icp-p2plane', 'doc/bench/ycbv_video0000_crops_plot.dat' using 27 title 'sacia+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 31 title 'prerej+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 35 title 'o3d-ransac+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 39 title 'o3d-fgr+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 43 title 'ppf+icp'
set ylabel '(b) rotation error (deg)'
plot 'doc/bench/ycbv_video0000_crops_plot.dat' using 5:xtic(1) title 'icf-fast', 'doc/bench/ycbv_video0000_crops_plot.dat' using 9 title 'icf-thesis', 'doc/bench/ycbv_video0000_crops_plot.dat' using 13 title 'icf-fast+sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 17 title 'icf-sac', 'doc/bench/ycbv_video0000_crops_plot.dat' using 21 title 'icp-p2p', 'doc/bench/ycbv_video0000_crops_plot.dat' using 25 title 'icp-p2plane', 'doc/bench/ycbv_video0000_crops_plot.dat' using 29 title 'sacia+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 33 title 'prerej+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 37 title 'o3d-ransac+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 41 title 'o3d-fgr+icp', 'doc/bench/ycbv_video0000_crops_plot.dat' using 45 title 'ppf+icp'
unset multiplot

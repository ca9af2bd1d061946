cd "/work/main/docs/results/colours"
set datafile missing 'nan'
set logscale x
set grid
set terminal pngcairo noenhanced size 1400,600 font ',10'
set output 'error_vs_frame_time.png'
set multiplot layout 1,2 title "colour edits and back light, 24 scenes (svbrdf default = one bounce; direct and colours without; tabulated direct and colours): error against frame time"
set xlabel "frame time (ms, CPU wall, median over scenes, log scale)"
set ylabel "PSNR against the ground truth (dB, median over scenes)"
set key top left
plot 'points.dat' index 0 using 3:5 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 3:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'points.dat' index 1 using 3:5 with points pt 5 ps 0.8 title "tabulated", '' index 1 using 3:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_frame_time_psnr.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
set xlabel "frame time (ms, CPU wall, median over scenes, log scale)"
set ylabel "perceptual error 1 - SSIM (median over scenes)"
set key bottom left
plot 'points.dat' index 0 using 3:6 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 3:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'points.dat' index 1 using 3:6 with points pt 5 ps 0.8 title "tabulated", '' index 1 using 3:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_frame_time_perceptual.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
unset multiplot
set output
set terminal svg noenhanced size 1400,600 font ',10' background '#ffffff'
set output 'error_vs_frame_time.svg'
set multiplot layout 1,2 title "colour edits and back light, 24 scenes (svbrdf default = one bounce; direct and colours without; tabulated direct and colours): error against frame time"
set xlabel "frame time (ms, CPU wall, median over scenes, log scale)"
set ylabel "PSNR against the ground truth (dB, median over scenes)"
set key top left
plot 'points.dat' index 0 using 3:5 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 3:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'points.dat' index 1 using 3:5 with points pt 5 ps 0.8 title "tabulated", '' index 1 using 3:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_frame_time_psnr.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
set xlabel "frame time (ms, CPU wall, median over scenes, log scale)"
set ylabel "perceptual error 1 - SSIM (median over scenes)"
set key bottom left
plot 'points.dat' index 0 using 3:6 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 3:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'points.dat' index 1 using 3:6 with points pt 5 ps 0.8 title "tabulated", '' index 1 using 3:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_frame_time_perceptual.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
unset multiplot
set output
set terminal pngcairo noenhanced size 1400,600 font ',10'
set output 'error_vs_precompute_time.png'
set multiplot layout 1,2 title "colour edits and back light, 24 scenes (svbrdf default = one bounce; direct and colours without; tabulated direct and colours): error against precompute time"
set xlabel "precompute time (s, log scale)"
set ylabel "PSNR against the ground truth (dB, median over scenes)"
set key top left
plot 'points.dat' index 0 using 4:5 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 4:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_precompute_time_psnr.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
set xlabel "precompute time (s, log scale)"
set ylabel "perceptual error 1 - SSIM (median over scenes)"
set key bottom left
plot 'points.dat' index 0 using 4:6 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 4:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_precompute_time_perceptual.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
unset multiplot
set output
set terminal svg noenhanced size 1400,600 font ',10' background '#ffffff'
set output 'error_vs_precompute_time.svg'
set multiplot layout 1,2 title "colour edits and back light, 24 scenes (svbrdf default = one bounce; direct and colours without; tabulated direct and colours): error against precompute time"
set xlabel "precompute time (s, log scale)"
set ylabel "PSNR against the ground truth (dB, median over scenes)"
set key top left
plot 'points.dat' index 0 using 4:5 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 4:5:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_precompute_time_psnr.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
set xlabel "precompute time (s, log scale)"
set ylabel "perceptual error 1 - SSIM (median over scenes)"
set key bottom left
plot 'points.dat' index 0 using 4:6 with points pt 7 ps 0.8 title "svbrdf", '' index 0 using 4:6:1 with labels font ',7' offset 0.5,0.5 left notitle, 'front_precompute_time_perceptual.dat' using 1:2 with linespoints lw 1.5 pt 6 ps 2 lc rgb 'black' title 'Pareto front'
unset multiplot
set output

# Vitis HLS: C simulation, synthesis and co-simulation of the ray-trace block against the
# golden model. From this directory, with the block's source in viray.cpp (viray.h is its
# interface), the staticlib built (`cargo build --release -p fpgfx-capi`) and vectors
# written (`fpgfx vectors render SCENE -o vectors --size 64x36`):
#
#   vitis_hls -f run_hls.tcl
#
# docs/hls-testbench.md explains each step.
set fpgfx [file normalize ../..]
set vectors [file normalize vectors]
set ldflags "-L$fpgfx/target/release -lfpgfx -lpthread -ldl -lm"

open_project -reset viray_prj
set_top viray
add_files viray.cpp -cflags "-I$fpgfx/capi/include"
add_files -tb tb_viray.cpp -cflags "-I$fpgfx/capi/include"
open_solution -reset solution1 -flow_target vivado
# The KCU116's Kintex UltraScale+ and the seed's 303 MHz.
set_part xcku5p-ffvb676-2-e
create_clock -period 3.3

csim_design -ldflags $ldflags -argv $vectors
csynth_design
cosim_design -ldflags $ldflags -argv $vectors
exit
